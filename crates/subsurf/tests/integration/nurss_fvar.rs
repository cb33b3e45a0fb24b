//! # Face-varying data (texture coordinates) under NURSS
//!
//! OpenSubdiv has no NURSS, so there is no oracle: a channel under NURSS is defined as the
//! NURSS refinement (and limit) of its value mesh (docs/nurss.md, "Texture coordinates"),
//! and checked here against what that definition must reproduce:
//!
//! - **Equal intervals** make NURSS Catmull-Clark: every OpenSubdiv regression shape with
//!   texture coordinates that NURSS accepts (no semi-sharp tags, no smooth-triangle rule),
//!   with interval 2.5 on every edge and weight 3 on every vertex, refines its `uv` channel
//!   as OpenSubdiv's face-varying refinement (`subdivide` with Catmull-Clark, itself checked
//!   against OpenSubdiv in `fvar_golden.rs`) corner for corner in all six modes, to 1e-12;
//!   and its limit surface is `FaceVaryingSurface::new`'s.
//! - **A channel laid out as the vertices** in mode `none`, an affine function of the
//!   positions, stays that function of the refined positions, of the limit positions, of
//!   the tessellation's samples and of the exact surface, with unequal and zero intervals,
//!   side intervals and rational weights.
//! - **Seams are boundaries**: each island of a channel cut by a seam refines as that island
//!   on its own (a mesh whose points are the values); every refined vertex off the seam has
//!   one value, every one on it two.
//! - Refining `a` then `b` levels (through the written mesh) equals refining `a + b`, with
//!   a seam whose two sides carry different side intervals.

use subsurf::limit::{FaceVaryingSurface, SurfacePoint};
use subsurf::mesh::{
    EdgeInterval, FaceVarying, FaceVaryingInterpolation as Mode, KnotTags, Options, PolyMesh,
    SideInterval, TriangleSubdivision, VertexWeight,
};
use subsurf::nonuniform::{tessellate, NurssError, NurssSurface};
use subsurf::{subdivide, Scheme, SubdivideOptions};

use crate::common::osd_shapes;

const MODES: [Mode; 6] = [
    Mode::None,
    Mode::CornersOnly,
    Mode::CornersPlus1,
    Mode::CornersPlus2,
    Mode::Boundaries,
    Mode::All,
];

/// The affine map the vertex-laid-out channels are: `uv = A x + b`.
fn affine(p: &[f64; 3]) -> [f64; 2] {
    [
        p[0] + 0.5 * p[1] - 0.25 * p[2] + 1.0,
        0.1 * p[0] - p[1] + 2.0 * p[2],
    ]
}

/// `mesh` with a `uv` channel laid out as its vertices, `affine` of the positions.
fn with_affine_channel(mut mesh: PolyMesh) -> PolyMesh {
    let values = mesh.positions().iter().flat_map(affine).collect();
    let indices = mesh.face_verts().to_vec();
    mesh.face_varying = vec![FaceVarying::new("uv", 2, values, indices).unwrap()];
    mesh
}

/// Every edge of `mesh` (as its faces list them, without degenerate ones) with the interval
/// `interval(a, b)` (`a < b`).
fn tag_intervals(mesh: &mut PolyMesh, interval: impl Fn(u32, u32) -> f64) {
    let mut k = KnotTags::default();
    for f in mesh.faces() {
        for i in 0..f.len() {
            let (a, b) = (f[i], f[(i + 1) % f.len()]);
            if a != b {
                let d = interval(a.min(b), a.max(b));
                k.intervals.push(EdgeInterval {
                    v0: a,
                    v1: b,
                    interval: d,
                });
            }
        }
    }
    mesh.knots = k;
}

/// Unequal intervals from the edge's ends: 0.25 to 3, and 0 on one edge in 17.
fn uneven(a: u32, b: u32) -> f64 {
    let h = (a.wrapping_mul(2_654_435_761) ^ b.wrapping_mul(40_503)) % 17;
    if h == 0 {
        0.0
    } else {
        0.25 + 2.75 * f64::from(h) / 16.0
    }
}

fn refine(mesh: &PolyMesh, options: Options, levels: u32, limit: bool) -> PolyMesh {
    let opts = SubdivideOptions {
        levels,
        scheme: Scheme::Nurss,
        options,
        limit,
        ..Default::default()
    };
    subdivide(mesh, &opts).expect("refines").mesh
}

/// The largest difference between the values of `a`'s and `b`'s first channels at every
/// face corner (the meshes having the same faces).
fn corner_difference(a: &PolyMesh, b: &PolyMesh) -> f64 {
    assert_eq!(a.face_offsets(), b.face_offsets());
    let (ua, ub) = (&a.face_varying[0], &b.face_varying[0]);
    assert_eq!(ua.indices().len(), a.face_verts().len());
    assert_eq!(ub.indices().len(), b.face_verts().len());
    let mut worst = 0.0f64;
    for (&i, &j) in ua.indices().iter().zip(ub.indices()) {
        for (x, y) in ua.value(i as usize).iter().zip(ub.value(j as usize)) {
            worst = worst.max((x - y).abs());
        }
    }
    worst
}

/// The size of a channel's values (for relative tolerances), at least 1.
fn value_scale(ch: &FaceVarying) -> f64 {
    ch.values().iter().fold(1.0, |m: f64, x| m.max(x.abs()))
}

/// With all intervals equal (2.5) and all weights equal (3), a channel refines as
/// Catmull-Clark's face-varying refinement, in every mode, on every OpenSubdiv shape with
/// texture coordinates that NURSS accepts.
#[test]
fn equal_intervals_refine_channels_as_catmull_clark() {
    let mut compared = 0;
    let mut worst = 0.0f64;
    for (name, mesh, options) in osd_shapes() {
        if mesh.face_varying.is_empty() || options.triangles == TriangleSubdivision::Smooth {
            continue; // NURSS has one rule for every face size.
        }
        let mut m = mesh.clone();
        if m.check_repeated_vertices().is_ok() {
            tag_intervals(&mut m, |_, _| 2.5);
        }
        m.knots.weights = (0..m.num_vertices() as u32)
            .map(|vertex| VertexWeight {
                vertex,
                weight: 3.0,
            })
            .collect();
        for mode in MODES {
            let options = Options {
                face_varying: mode,
                ..options
            };
            for levels in 1..=2 {
                let opts = |scheme| SubdivideOptions {
                    levels,
                    scheme,
                    options,
                    ..Default::default()
                };
                let nurss = match subdivide(&m, &opts(Scheme::Nurss)) {
                    Ok(s) => s.mesh,
                    Err(subsurf::Error::Nurss(NurssError::SemiSharp { .. })) => continue,
                    Err(e) => panic!("{name}: {e}"),
                };
                let cc = subdivide(&mesh, &opts(Scheme::CatmullClark)).unwrap().mesh;
                let d = corner_difference(&nurss, &cc) / value_scale(&cc.face_varying[0]);
                assert!(d <= 1e-12, "{name} {mode} level {levels}: {d:e}");
                worst = worst.max(d);
                compared += 1;
            }
        }
    }
    eprintln!("{compared} cases, largest difference {worst:e}");
    assert!(compared >= 40 * 12, "only {compared} cases compared");
}

/// `mesh` with unequal intervals (zero ones included), rational weights and side intervals
/// on its first face.
fn non_uniform(mut mesh: PolyMesh) -> PolyMesh {
    tag_intervals(&mut mesh, uneven);
    mesh.knots.weights = (0..mesh.num_vertices() as u32)
        .map(|vertex| VertexWeight {
            vertex,
            weight: 1.0 + 0.5 * f64::from(vertex % 3),
        })
        .collect();
    let f0 = mesh.face(0).to_vec();
    for (j, &a) in f0.iter().enumerate() {
        mesh.knots.side_intervals.push(SideInterval {
            face: 0,
            v0: a,
            v1: f0[(j + 1) % f0.len()],
            interval: 0.5 + 0.4 * j as f64,
        });
    }
    mesh
}

/// Checks that every corner of `m`'s channel is `affine` of its vertex's position; returns
/// the largest difference relative to the positions' size.
fn check_affine(m: &PolyMesh, what: &str) -> f64 {
    let uv = &m.face_varying[0];
    let scale = (m.positions().iter().flatten()).fold(1.0, |s: f64, x| s.max(x.abs()));
    let mut worst = 0.0f64;
    for (&v, &i) in m.face_verts().iter().zip(uv.indices()) {
        let want = affine(&m.positions()[v as usize]);
        for (x, y) in uv.value(i as usize).iter().zip(want) {
            worst = worst.max((x - y).abs() / scale);
        }
    }
    assert!(worst <= 1e-12, "{what}: {worst:e}");
    worst
}

/// A channel laid out as the vertices in mode `none`, an affine function of the positions,
/// stays that function of the refined positions, of the limit positions and of the
/// tessellation's samples, with unequal and zero intervals, side intervals and weights
/// (unweighted values would not: the weights do not cancel). The shapes are manifold: at a
/// non-manifold vertex the value mesh is a corner, as OpenSubdiv's face-varying rules make
/// it, where the mesh is not.
#[test]
fn affine_channels_follow_the_positions() {
    let names = [
        "catmark_hole_test1",
        "catmark_nonquads",
        "catmark_pyramid",
        "catmark_torus",
        "catmark_xord_boundary",
        "catmark_xord_interior",
    ];
    let mut worst = 0.0f64;
    for (name, mesh, options) in osd_shapes() {
        if !names.contains(&name.as_str()) {
            continue;
        }
        let m = non_uniform(with_affine_channel(mesh));
        let options = Options {
            face_varying: Mode::None,
            ..options
        };
        for levels in 1..=3 {
            for limit in [false, true] {
                let out = refine(&m, options, levels, limit);
                let what = format!("{name} level {levels} limit {limit}");
                worst = worst.max(check_affine(&out, &what));
            }
        }
        let t = tessellate(&m, &options, 4, true).expect("tessellates");
        let sampled = t.to_polymesh().expect("a valid mesh");
        worst = worst.max(check_affine(&sampled, &format!("{name} tessellated")));
    }
    eprintln!("largest difference {worst:e}");
}

/// A 4 × 4 grid of quads (vertex `(i, j)` is `5 j + i`) whose `uv` channel is cut along the
/// column `i = 2`: the faces left of it and right of it are two islands, the right one's
/// values shifted by `(0.25, 0)`; unequal intervals, and with `weights` rational weights.
fn seam_grid(weights: bool) -> PolyMesh {
    let p = (0..25)
        .map(|v| {
            [
                f64::from(v % 5),
                f64::from(v / 5),
                0.1 * f64::from((v * v) % 7),
            ]
        })
        .collect();
    let faces: Vec<[u32; 4]> = (0..16u32)
        .map(|f| {
            let v = 5 * (f / 4) + f % 4;
            [v, v + 1, v + 6, v + 5]
        })
        .collect();
    let mut m = PolyMesh::from_faces(p, &faces).unwrap();
    // Left island: value v for vertex v (i ≤ 2); right island: 25 + v (i ≥ 2).
    let mut values = Vec::new();
    for shift in [0.0, 0.25] {
        for v in 0..25u32 {
            values.extend([f64::from(v % 5) / 4.0 + shift, f64::from(v / 5) / 4.0]);
        }
    }
    let indices = (faces.iter())
        .flat_map(|f| {
            let right = f[0] % 5 >= 2;
            f.map(|v| if right { 25 + v } else { v })
        })
        .collect();
    m.face_varying = vec![FaceVarying::new("uv", 2, values, indices).unwrap()];
    tag_intervals(&mut m, uneven);
    if weights {
        m.knots.weights = (0..25u32)
            .map(|vertex| VertexWeight {
                vertex,
                weight: 1.0 + 0.25 * f64::from(vertex % 4),
            })
            .collect();
    }
    m
}

/// Island `right` of `m`'s channel (see [`seam_grid`]) as a mesh of its own: its faces
/// through its values, the values as points, the intervals and weights of the mesh
/// edges they lie on.
fn island(m: &PolyMesh, right: bool) -> PolyMesh {
    let uv = &m.face_varying[0];
    let faces: Vec<usize> = (0..m.num_faces())
        .filter(|&f| (m.face(f)[0] % 5 >= 2) == right)
        .collect();
    let mut ids = std::collections::BTreeMap::new();
    let mut points = Vec::new();
    let mut vertex_of = Vec::new();
    let mut island_faces = Vec::new();
    for &f in &faces {
        let o = m.face_offsets()[f] as usize;
        let corners: Vec<u32> = (0..4)
            .map(|k| {
                let x = uv.indices()[o + k];
                *ids.entry(x).or_insert_with(|| {
                    let v = uv.value(x as usize);
                    points.push([v[0], v[1], 0.0]);
                    vertex_of.push(m.face(f)[k]);
                    (points.len() - 1) as u32
                })
            })
            .collect();
        island_faces.push([corners[0], corners[1], corners[2], corners[3]]);
    }
    let mut out = PolyMesh::from_faces(points, &island_faces).unwrap();
    let mesh_interval = |a: u32, b: u32| {
        (m.knots.intervals.iter())
            .rev()
            .find(|t| (t.v0, t.v1) == (a, b) || (t.v0, t.v1) == (b, a))
            .map_or(1.0, |t| t.interval)
    };
    tag_intervals(&mut out, |a, b| {
        mesh_interval(vertex_of[a as usize], vertex_of[b as usize])
    });
    out
}

/// A seam is a boundary: each island refines as the island on its own (in mode `none`,
/// and in `corners-only`, whose single-face corners are the island's edge-and-corner
/// corners), and every refined vertex has one value off the seam and two on it. (With
/// rational weights the seam's values take the mesh's weights on every level, which an
/// island refined on its own does not: see [`refining_twice_equals_refining_once`].)
#[test]
fn seams_are_boundaries() {
    let m = seam_grid(false);
    for (mode, boundary) in [
        (Mode::None, subsurf::mesh::BoundaryInterpolation::EdgeOnly),
        (
            Mode::CornersOnly,
            subsurf::mesh::BoundaryInterpolation::EdgeAndCorner,
        ),
    ] {
        let options = Options {
            face_varying: mode,
            ..Options::default()
        };
        for levels in 1..=3u32 {
            let out = refine(&m, options, levels, false);
            let uv = &out.face_varying[0];
            // Base face f's descendants are faces 4^(L−1) · [4 f, 4 f + 4) (quads).
            let per = 4usize.pow(levels);
            for right in [false, true] {
                let isl = island(&m, right);
                let island_options = Options {
                    boundary,
                    ..Options::default()
                };
                let got = refine(&isl, island_options, levels, false);
                let base: Vec<usize> = (0..16).filter(|f| (f % 4 >= 2) == right).collect();
                let mut k = 0;
                for f in base {
                    for slot in 4 * per * f..4 * per * (f + 1) {
                        let want = got.positions()[got.face_verts()[k] as usize];
                        let v = uv.value(uv.indices()[slot] as usize);
                        let d = (v[0] - want[0]).abs().max((v[1] - want[1]).abs());
                        assert!(d <= 1e-12, "{mode} level {levels} island {right}: {d:e}");
                        k += 1;
                    }
                }
                assert_eq!(k, got.face_verts().len());
            }
            // One value per vertex off the seam, two on it (its 4 · 2^L + 1 vertices).
            let mut values = vec![std::collections::BTreeSet::new(); out.num_vertices()];
            for (&v, &x) in out.face_verts().iter().zip(uv.indices()) {
                values[v as usize].insert(x);
            }
            let on_seam = values.iter().filter(|s| s.len() == 2).count();
            assert!(values.iter().all(|s| (1..=2).contains(&s.len())));
            assert_eq!(on_seam, 4 * (1 << levels) + 1, "{mode} level {levels}");
        }
    }
}

/// Refining `a` levels, then `b` levels of the result, equals refining `a + b` levels, in
/// every mode, with rational weights and a seam whose two sides carry different side
/// intervals (each value level takes the mesh level's intervals, weights and mode rules, as
/// the written level has them); and the limit of a level is the limit of the level as
/// written.
#[test]
fn refining_twice_equals_refining_once() {
    let mut m = seam_grid(true);
    for j in 0..4u32 {
        let (a, b) = (5 * j + 2, 5 * j + 7);
        for (face, d) in [(4 * j + 1, 0.5), (4 * j + 2, 2.0)] {
            m.knots.side_intervals.push(SideInterval {
                face,
                v0: a,
                v1: b,
                interval: d,
            });
        }
    }
    for mode in MODES {
        let options = Options {
            face_varying: mode,
            ..Options::default()
        };
        let once = refine(&m, options, 3, false);
        let twice = refine(&refine(&m, options, 1, false), options, 2, false);
        let d = corner_difference(&once, &twice);
        assert!(d <= 1e-12, "{mode}: {d:e}");
        let limit = refine(&m, options, 2, true);
        let written = refine(&refine(&m, options, 2, false), options, 0, true);
        let d = corner_difference(&limit, &written);
        assert!(d <= 1e-12, "{mode} limit: {d:e}");
    }
}

/// The limit values at a vertex of `coarse` (a level's limit) and at the same vertex of
/// `fine` (a finer level's, whose first vertices are the coarse level's): the largest
/// difference between their sorted sets of values.
fn limit_difference(coarse: &PolyMesh, fine: &PolyMesh) -> f64 {
    let sets = |m: &PolyMesh| {
        let uv = &m.face_varying[0];
        let mut s = vec![Vec::new(); coarse.num_vertices()];
        for (&v, &x) in m.face_verts().iter().zip(uv.indices()) {
            if (v as usize) < s.len() {
                let p = uv.value(x as usize);
                if !s[v as usize].iter().any(|q: &[f64; 2]| q == &[p[0], p[1]]) {
                    s[v as usize].push([p[0], p[1]]);
                }
            }
        }
        for x in &mut s {
            x.sort_by(|a, b| a.partial_cmp(b).unwrap());
        }
        s
    };
    let (a, b) = (sets(coarse), sets(fine));
    let mut worst = 0.0f64;
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(x.len(), y.len());
        for (p, q) in x.iter().zip(y) {
            worst = worst.max((p[0] - q[0]).abs()).max((p[1] - q[1]).abs());
        }
    }
    worst
}

/// The limit of a channel is the same from every level (as the positions' is) where the
/// value levels are the base value mesh refined on its own: without rational weights. With
/// them, next to a seam the levels' limits differ a little, less with each level (the
/// price of taking the mesh's weights on every level, docs/nurss.md): measured here.
#[test]
fn limits_of_successive_levels() {
    for weights in [false, true] {
        let m = seam_grid(weights);
        for mode in [Mode::None, Mode::CornersOnly, Mode::Boundaries] {
            let options = Options {
                face_varying: mode,
                ..Options::default()
            };
            let lim: Vec<PolyMesh> = (1..=3).map(|l| refine(&m, options, l, true)).collect();
            let (d12, d23) = (
                limit_difference(&lim[0], &lim[1]),
                limit_difference(&lim[1], &lim[2]),
            );
            eprintln!("weights {weights} {mode}: levels 1-2 {d12:e}, 2-3 {d23:e}");
            if weights {
                assert!(d23 < d12 && d12 < 1e-3, "{mode}: {d12:e} {d23:e}");
            } else {
                assert!(d12 <= 1e-14 && d23 <= 1e-14, "{mode}: {d12:e} {d23:e}");
            }
        }
    }
}

/// Points on every (sub-)face of `mesh` but its holes.
fn sample_points(mesh: &PolyMesh) -> Vec<SurfacePoint> {
    let mut out = Vec::new();
    for f in (0..mesh.num_faces()).filter(|f| !mesh.tags.holes.contains(&(*f as u32))) {
        let n = mesh.face(f).len();
        for subface in 0..if n == 4 { 1 } else { n as u32 } {
            for (u, v) in [(0.5, 0.5), (0.0, 0.0), (1.0, 0.25), (0.3, 0.8)] {
                out.push(SurfacePoint {
                    face: f as u32,
                    subface,
                    u,
                    v,
                });
            }
        }
    }
    out
}

/// With all intervals equal (2.5) and all weights equal (3), the exact surface of a
/// channel ([`FaceVaryingSurface::nurss`]) is Catmull-Clark's ([`FaceVaryingSurface::new`],
/// checked against OpenSubdiv's `Bfr` in `fvar_limit_golden.rs`), in every mode, value and
/// derivatives, and exact on every face.
#[test]
fn equal_intervals_give_catmull_clarks_exact_surface() {
    let (mut compared, mut worst) = (0, [0.0f64; 2]);
    let hole = |e: &subsurf::limit::EvalError| matches!(e, subsurf::limit::EvalError::Hole { .. });
    for (name, mesh, options) in osd_shapes() {
        if mesh.face_varying.is_empty()
            || options.triangles == TriangleSubdivision::Smooth
            || mesh.num_faces() > 400
        {
            continue;
        }
        let mut m = mesh.clone();
        if m.check_repeated_vertices().is_ok() {
            tag_intervals(&mut m, |_, _| 2.5);
        }
        m.knots.weights = (0..m.num_vertices() as u32)
            .map(|vertex| VertexWeight {
                vertex,
                weight: 3.0,
            })
            .collect();
        let points = sample_points(&mesh);
        for mode in MODES {
            let options = Options {
                face_varying: mode,
                ..options
            };
            let nurss = match FaceVaryingSurface::nurss(&m, options, 0) {
                Ok(s) => s,
                Err(subsurf::limit::FaceVaryingError::Nurss(NurssError::SemiSharp { .. })) => {
                    continue
                }
                Err(e) => panic!("{name}: {e}"),
            };
            let cc = FaceVaryingSurface::new(&mesh, options, 0).unwrap();
            // Faces that are holes (boundary interpolation `none` makes some) have no surface.
            let points: Vec<SurfacePoint> = (points.iter().copied())
                .filter(|&p| match (nurss.eval_point(p), cc.eval_point(p)) {
                    (Ok(_), Ok(_)) => true,
                    (Err(x), Err(y)) if hole(&x) && hole(&y) => false,
                    (x, y) => panic!("{name} {mode} {p:?}: {x:?} vs {y:?}"),
                })
                .collect();
            let (a, b) = (
                nurss.eval_many(&points).unwrap(),
                cc.eval_many(&points).unwrap(),
            );
            let scale = value_scale(&mesh.face_varying[0]);
            let diff = |x: &[f64], y: &[f64]| {
                x.iter()
                    .zip(y)
                    .fold(0.0f64, |d, (p, q)| d.max((p - q).abs()))
                    / scale
            };
            let (dv, dd) = (
                diff(&a.value, &b.value),
                diff(&a.du, &b.du).max(diff(&a.dv, &b.dv)),
            );
            assert!(dv <= 1e-12 && dd <= 1e-11, "{name} {mode}: {dv:e} {dd:e}");
            worst = [worst[0].max(dv), worst[1].max(dd)];
            compared += 1;
        }
    }
    eprintln!("{compared} cases, largest differences {worst:?}");
    assert!(compared >= 40 * 6, "only {compared} cases compared");
}

/// An `n × m` torus of quads (vertex `(i, j)` is `n j + i`) with tensor-product intervals
/// (`du[i]` on the edges from column `i` to `i + 1`, `dv[j]` from row `j` to `j + 1`) and
/// weights `wu[i] wv[j]`.
fn torus(n: u32, m: u32) -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..m {
        for i in 0..n {
            let (a, b) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(m),
            );
            p.push([
                (2.0 + b.cos()) * a.cos(),
                (2.0 + b.cos()) * a.sin(),
                b.sin(),
            ]);
        }
    }
    let id = |i: u32, j: u32| (j % m) * n + i % n;
    let faces: Vec<[u32; 4]> = (0..m)
        .flat_map(|j| (0..n).map(move |i| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
        .collect();
    let mut t = PolyMesh::from_faces(p, &faces).unwrap();
    let du = |i: u32| 0.5 + 0.3 * f64::from(i % 4);
    let dv = |j: u32| 1.0 + 0.7 * f64::from(j % 3);
    for j in 0..m {
        for i in 0..n {
            let (a, b, c) = (id(i, j), id(i + 1, j), id(i, j + 1));
            t.knots.intervals.push(EdgeInterval {
                v0: a,
                v1: b,
                interval: du(i),
            });
            t.knots.intervals.push(EdgeInterval {
                v0: a,
                v1: c,
                interval: dv(j),
            });
            t.knots.weights.push(VertexWeight {
                vertex: a,
                weight: (1.0 + 0.2 * f64::from(i % 3)) * (1.0 + 0.1 * f64::from(j % 2)),
            });
        }
    }
    t
}

/// A channel laid out as the vertices, an affine function of the positions, has the exact
/// surface `A x + b` of the surface's exact points `x` (and derivatives `A ∂x`) on a torus
/// with tensor-product intervals and weights, every face a rational bicubic span; in mode
/// `all` it is bilinear per face instead, as Catmull-Clark's.
#[test]
fn exact_surface_of_an_affine_channel_is_affine() {
    let m = with_affine_channel(torus(8, 6));
    let options = Options {
        face_varying: Mode::None,
        ..Options::default()
    };
    let uv = FaceVaryingSurface::nurss(&m, options, 0).unwrap();
    let surface = NurssSurface::new(&m, &options).unwrap();
    let points = sample_points(&m);
    let got = uv.eval_many(&points).unwrap();
    let a = |x: [f64; 3]| {
        let (p, o) = (affine(&x), affine(&[0.0; 3]));
        [p[0] - o[0], p[1] - o[1]]
    };
    for (i, &p) in points.iter().enumerate() {
        let d = surface.eval_point(p).unwrap();
        let want = [affine(&d.p), a(d.du), a(d.dv)];
        let have = [&got.value, &got.du, &got.dv].map(|c| [c[2 * i], c[2 * i + 1]]);
        for (w, h) in want.iter().zip(&have) {
            let e = (w[0] - h[0]).abs().max((w[1] - h[1]).abs());
            assert!(e <= 1e-12 * 8.0, "{p:?}: {w:?} vs {h:?}");
        }
    }
    let linear = Options {
        face_varying: Mode::All,
        ..options
    };
    let nurss = FaceVaryingSurface::nurss(&m, linear, 0).unwrap();
    let cc = FaceVaryingSurface::new(&m, linear, 0).unwrap();
    assert_eq!(
        nurss.eval_many(&points).unwrap(),
        cc.eval_many(&points).unwrap()
    );
}

/// A seam is a boundary of the exact surface too: on a torus cut along the ring of column
/// 0 (the faces of the last column give it values shifted by `(1, 0)`), the faces whose
/// 4 × 4 net of values does not reach the seam are exact spans (the affine channel), and
/// those next to it, where the value mesh has a boundary with unequal intervals, are
/// refused, naming the face.
#[test]
fn faces_next_to_a_seam_are_not_exact() {
    let (n, rows) = (8u32, 6u32);
    let mut m = with_affine_channel(torus(n, rows));
    let ch = &m.face_varying[0];
    let mut values = ch.values().to_vec();
    let mut indices = ch.indices().to_vec();
    for j in 0..rows {
        let v = (j * n) as usize;
        values.extend([values[2 * v] + 1.0, values[2 * v + 1]]);
        // Face (n − 1, j) and (n − 1, j − 1) reach column 0 through their corners 1 and 2.
        let shifted = (values.len() / 2 - 1) as u32;
        let f = (j * n + n - 1) as usize;
        let g = (((j + rows - 1) % rows) * n + n - 1) as usize;
        indices[4 * f + 1] = shifted;
        indices[4 * g + 2] = shifted;
    }
    m.face_varying = vec![FaceVarying::new("uv", 2, values, indices).unwrap()];
    let options = Options {
        face_varying: Mode::None,
        ..Options::default()
    };
    let uv = FaceVaryingSurface::nurss(&m, options, 0).unwrap();
    let surface = NurssSurface::new(&m, &options).unwrap();
    for f in 0..m.num_faces() as u32 {
        let p = SurfacePoint {
            face: f,
            subface: 0,
            u: 0.4,
            v: 0.6,
        };
        let column = f % n;
        match uv.eval_point(p) {
            Ok(x) if (2..n - 2).contains(&column) => {
                let want = affine(&surface.eval_point(p).unwrap().p);
                let e = (x.value[0] - want[0])
                    .abs()
                    .max((x.value[1] - want[1]).abs());
                assert!(e <= 1e-11, "face {f}: {e:e}");
            }
            Err(subsurf::limit::EvalError::NotExact { face, .. })
                if !(2..n - 2).contains(&column) =>
            {
                assert_eq!(face, f);
            }
            other => panic!("face {f} (column {column}): {other:?}"),
        }
    }
}

/// Re-posing with NURSS (`Reposer`) carries the refined channels, and with `limit` their
/// limit, as `subdivide` gives them: texture coordinates do not depend on the pose.
#[test]
fn reposing_carries_the_channels() {
    let m = seam_grid(true);
    let mut values = Vec::new();
    for limit in [false, true] {
        let opts = SubdivideOptions {
            levels: 2,
            scheme: Scheme::Nurss,
            options: Options {
                face_varying: Mode::CornersOnly,
                ..Options::default()
            },
            limit,
            ..Default::default()
        };
        let want = subdivide(&m, &opts).unwrap().mesh;
        let mut r = subsurf::Reposer::new(&m, &opts).unwrap();
        let moved: Vec<[f64; 3]> = m
            .positions()
            .iter()
            .map(|p| [p[0], p[1], p[2] + p[0]])
            .collect();
        let posed = r.pose(&moved).unwrap();
        assert_eq!(want.face_varying.len(), 1, "the channel is written");
        assert_eq!(posed.face_varying, want.face_varying, "limit {limit}");
        values.push(want.face_varying[0].values().to_vec());
    }
    assert_ne!(values[0], values[1], "the limit moves the values");
}
