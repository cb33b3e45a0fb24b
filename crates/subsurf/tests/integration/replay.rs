//! # Re-posing plans agree with full refinement
//!
//! [`RefinePlan`] precomputes the linear map from base positions to refined positions. On
//! every OpenSubdiv regression shape (`tests/shapes/osd/*.obj`, which cover boundaries in
//! all modes, infinite and semi-sharp creases, corners, Chaikin, holes, n-gons, triangles,
//! non-manifold topology), with the scheme options of the shape's tags, and for levels 1 to
//! 3 (and 4 on shapes with faces that are not quads, whose ring patches then refine four
//! levels at once), `plan.apply` must equal the positions of [`subdivide`], index for index, within
//! `1e-14 ×` the bounding-box diagonal of the input — both on the original positions and
//! after moving every vertex (the plan does not depend on positions). The same holds for
//! the plans of mixed subdivision (the shape-adjustable scheme on the first levels) against
//! [`subdivide`] with `Scheme::Adjustable`, for [`subsurf::Reposer`] with the limit, and for
//! Loop (its 25 shapes) and bilinear (its 3 shapes and every Catmull-Clark shape), plans
//! and re-posed limits.

use subsurf::io::read_obj;
use subsurf::mesh::{
    EdgeInterval, KnotTags, Options, PolyMesh, SideInterval, VertexWeight, SHARPNESS_INFINITE,
};
use subsurf::nonuniform;
use subsurf::refine::{PlanScratch, RefinePlan};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, Scheme, SubdivideOptions};

use crate::common::{osd_shapes, osd_shapes_dir, osd_shapes_of, Rng};

/// Tolerance relative to the input's bounding-box diagonal.
const REL_TOL: f64 = 1e-14;

fn diagonal(p: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in p {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    (0..3)
        .map(|k| (hi[k] - lo[k]).powi(2))
        .sum::<f64>()
        .sqrt()
        .max(f64::MIN_POSITIVE)
}

/// The largest coordinate difference, and where.
fn max_diff(a: &[[f64; 3]], b: &[[f64; 3]]) -> (f64, usize) {
    assert_eq!(a.len(), b.len());
    let mut worst = (0.0, 0);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        for k in 0..3 {
            let d = (x[k] - y[k]).abs();
            if d > worst.0 || d.is_nan() {
                worst = (d, i);
            }
        }
    }
    worst
}

/// A smooth, non-affine deformation (so that moved meshes are not just transformed ones).
fn deform(p: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let d = diagonal(p);
    p.iter()
        .enumerate()
        .map(|(i, x)| {
            let t = i as f64 * 0.618;
            [
                x[0] + 0.1 * d * (x[1] / d * 3.0 + t).sin(),
                x[1] * 1.3 + 0.05 * d * (x[2] / d * 5.0).cos(),
                x[2] - 0.2 * x[0] + 0.07 * d * t.cos(),
            ]
        })
        .collect()
}

fn subdivided(mesh: &PolyMesh, options: Options, levels: u32) -> Vec<[f64; 3]> {
    let opts = SubdivideOptions {
        levels,
        options,
        ..SubdivideOptions::default()
    };
    subdivide(mesh, &opts)
        .expect("subdivide")
        .mesh
        .positions()
        .to_vec()
}

#[test]
fn plan_equals_subdivide_on_all_shapes() {
    let mut failures = Vec::new();
    let mut cases = 0;
    let mut worst = (0.0, String::new());
    for (name, mesh, options) in osd_shapes() {
        let mut moved = mesh.clone();
        moved
            .positions_mut()
            .copy_from_slice(&deform(mesh.positions()));
        // Level 4 where the base mesh has faces that are not quads: their ring patches
        // then refine four levels at once.
        let non_quads = (0..mesh.num_faces()).any(|f| mesh.face(f).len() != 4);
        for levels in 1..=3 + u32::from(non_quads) {
            let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, levels).expect("plan");
            assert_eq!(plan.levels(), levels, "{name}");
            for (what, m) in [("original", &mesh), ("moved", &moved)] {
                let want = subdivided(m, options, levels);
                let got = plan.apply(m.positions());
                assert_eq!(plan.num_vertices(), want.len(), "{name} level {levels}");
                assert_eq!(got.len(), want.len(), "{name} level {levels}");
                let tol = REL_TOL * diagonal(m.positions());
                let (d, at) = max_diff(&got, &want);
                if d / tol > worst.0 {
                    worst = (d / tol, format!("{name} level {levels} {what}"));
                }
                if d > tol || d.is_nan() {
                    failures.push(format!(
                        "{name} level {levels} {what}: vertex {at} differs by {d:e} (tolerance {tol:e})"
                    ));
                }
                cases += 1;
            }
        }
    }
    println!(
        "{cases} cases; largest difference {:.3e} of the diagonal ({})",
        worst.0 * REL_TOL,
        worst.1
    );
    assert!(cases >= 560);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Mixed subdivision (the shape-adjustable masks on the first levels, then Catmull-Clark)
/// re-posed on every regression shape: `RefinePlan::new` with `Scheme::Adjustable` equals `subdivide`
/// within `1e-14 ×` the diagonal at levels 1–4, with `c` = 0 (the bilinear refinement of
/// the control mesh), 0.3 and 0.8, adjusted at every level (the plan's patches then apply
/// the adjustable masks), at the first one and at the first two (Catmull-Clark's patches
/// compute the last levels).
#[test]
fn mixed_plan_equals_subdivide_mixed_on_all_shapes() {
    let mut failures = Vec::new();
    let mut cases = 0;
    let schemes = [(0.0, u32::MAX), (0.3, 1), (0.8, 2), (0.3, u32::MAX)];
    let mut patches = [0; 4];
    for (name, mesh, options) in osd_shapes() {
        let mut moved = mesh.clone();
        moved
            .positions_mut()
            .copy_from_slice(&deform(mesh.positions()));
        for (i, (c, steps)) in schemes.into_iter().enumerate() {
            let mixed = Mixed {
                scheme: Adjustable::new(c).expect("c in [0, 1]"),
                steps,
            };
            for levels in 1..=4 {
                let plan = RefinePlan::new(&mesh, Scheme::Adjustable(mixed), options, levels)
                    .expect("plan");
                assert_eq!(plan.levels(), levels, "{name}");
                patches[i] += plan.num_patches();
                for (what, m) in [("original", &mesh), ("moved", &moved)] {
                    let opts = SubdivideOptions {
                        levels,
                        options,
                        ..SubdivideOptions::default()
                    };
                    let want = subdivide(
                        m,
                        &SubdivideOptions {
                            scheme: Scheme::Adjustable(mixed),
                            ..opts.clone()
                        },
                    )
                    .expect("subdivide");
                    let got = plan.apply(m.positions());
                    let tol = REL_TOL * diagonal(m.positions());
                    let (d, at) = max_diff(&got, want.mesh.positions());
                    if d > tol || d.is_nan() {
                        failures.push(format!(
                            "{name} c {c} steps {steps} level {levels} {what}: vertex {at} \
                             differs by {d:e} (tolerance {tol:e})"
                        ));
                    }
                    cases += 1;
                }
            }
        }
    }
    assert!(cases >= 2500, "{cases} cases");
    assert!(patches.iter().all(|&n| n > 1000), "patches {patches:?}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `mesh` with random knot tags: an interval on every edge (a tenth of them zero, which
/// makes sharp features), auxiliary intervals on a fifth of the face sides, and, if
/// `rational`, a weight in [0.5, 2] on every vertex; semi-sharp creases and corners made
/// infinitely sharp (NURSS has no semi-sharp rule).
fn with_knots(mesh: &PolyMesh, seed: u64, rational: bool) -> PolyMesh {
    let mut rng = Rng(seed | 1);
    let mut m = mesh.clone();
    let mut k = KnotTags::default();
    let faces: Vec<Vec<u32>> = m.faces().map(<[u32]>::to_vec).collect();
    for (f, fv) in faces.iter().enumerate() {
        for i in 0..fv.len() {
            let (v0, v1) = (fv[i], fv[(i + 1) % fv.len()]);
            if v0 == v1 {
                continue; // a degenerate edge, which no tag can name
            }
            let interval = if rng.next() < -0.4 {
                0.0
            } else {
                1.6 + 3.0 * rng.next()
            };
            k.intervals.push(EdgeInterval { v0, v1, interval });
            if rng.next() < -0.3 {
                let interval = 1.6 + 3.0 * rng.next();
                k.side_intervals.push(SideInterval {
                    face: f as u32,
                    v0,
                    v1,
                    interval,
                });
            }
        }
    }
    if rational {
        for vertex in 0..m.num_vertices() as u32 {
            let weight = 1.25 + 1.5 * rng.next();
            k.weights.push(VertexWeight { vertex, weight });
        }
    }
    m.knots = k;
    for c in &mut m.tags.creases {
        if c.sharpness > 0.0 {
            c.sharpness = c.sharpness.max(SHARPNESS_INFINITE);
        }
    }
    for c in &mut m.tags.corners {
        if c.sharpness > 0.0 {
            c.sharpness = c.sharpness.max(SHARPNESS_INFINITE);
        }
    }
    m
}

/// Non-uniform subdivision (NURSS, [JOS 2003]) re-posed on every regression shape, with
/// random knot intervals (zero ones included), auxiliary side intervals, and rational
/// weights on every other shape: `RefinePlan::new` with `Scheme::Nurss` applied to the homogeneous points
/// `(w x, w y, w z, w)`, divided by `w`, equals `subdivide` within `1e-14 ×` the
/// diagonal at levels 1–3, before and after moving the vertices.
#[test]
fn nurss_plan_equals_nurss_subdivide_on_all_shapes() {
    let mut failures = Vec::new();
    let (mut cases, mut rational_cases) = (0, 0);
    for (i, (name, mesh, options)) in osd_shapes().into_iter().enumerate() {
        let rational = i % 2 == 1;
        let mesh = with_knots(&mesh, 1000 + i as u64, rational);
        let mut moved = mesh.clone();
        moved
            .positions_mut()
            .copy_from_slice(&deform(mesh.positions()));
        for levels in 1..=3 {
            let plan = match RefinePlan::new(&mesh, Scheme::Nurss, options, levels) {
                Ok(plan) => plan,
                Err(e) => panic!("{name} level {levels}: {e}"),
            };
            assert_eq!((plan.num_patches(), plan.levels()), (0, levels));
            for (what, m) in [("original", &mesh), ("moved", &moved)] {
                let opts = SubdivideOptions {
                    scheme: Scheme::Nurss,
                    levels,
                    options,
                    ..Default::default()
                };
                let want = subdivide(m, &opts).expect("subdivide");
                let mut w = vec![1.0; m.num_vertices()];
                for t in &m.knots.weights {
                    w[t.vertex as usize] = t.weight;
                }
                let homogeneous: Vec<[f64; 4]> = (m.positions().iter().zip(&w))
                    .map(|(p, &w)| [w * p[0], w * p[1], w * p[2], w])
                    .collect();
                let got: Vec<[f64; 3]> = (plan.apply(&homogeneous).iter())
                    .map(|h| [h[0] / h[3], h[1] / h[3], h[2] / h[3]])
                    .collect();
                let tol = REL_TOL * diagonal(m.positions());
                let (d, at) = max_diff(&got, want.mesh.positions());
                if d > tol || d.is_nan() {
                    failures.push(format!(
                        "{name} level {levels} {what} (rational: {rational}): vertex {at} \
                         differs by {d:e} (tolerance {tol:e})"
                    ));
                }
                cases += 1;
                rational_cases += usize::from(rational);
            }
        }
    }
    assert!(cases >= 500 && rational_cases >= 240, "{cases} cases");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `Reposer::new` with `Scheme::Nurss` poses a rational mesh as `subdivide` refines it, pose
/// after pose (the weights stay with the vertices), and keeps the refined intervals and
/// weights as tags; with the limit too, at levels 0–2 (at level 0 the limit reads the
/// base mesh's triangles through the one step that makes them quads); it refuses semi-sharp
/// creases with a typed error.
#[test]
fn nurss_reposer_poses_rational_meshes() {
    let (bishop, options) = load("catmark_bishop");
    let mesh = with_knots(&bishop, 7, true);
    let opts = SubdivideOptions {
        levels: 2,
        scheme: Scheme::Nurss,
        options,
        ..SubdivideOptions::default()
    };
    for (levels, limit) in [(2, false), (0, true), (1, true), (2, true)] {
        let opts = SubdivideOptions {
            levels,
            limit,
            ..opts.clone()
        };
        let mut reposer = subsurf::Reposer::new(&mesh, &opts).expect("reposer");
        assert!(reposer.normals().is_none());
        let nurss_opts = SubdivideOptions {
            scheme: Scheme::Nurss,
            levels,
            options,
            limit,
            ..Default::default()
        };
        let mut m = mesh.clone();
        for pose in 0..3 {
            if pose > 0 {
                let next = deform(m.positions());
                m.positions_mut().copy_from_slice(&next);
            }
            let want = subdivide(&m, &nurss_opts).expect("subdivide").mesh;
            let got = reposer.pose(m.positions()).expect("pose");
            let (d, at) = max_diff(got.positions(), want.positions());
            assert!(
                d <= REL_TOL * diagonal(m.positions()),
                "level {levels}, limit {limit}, pose {pose}: vertex {at} differs by {d:e}"
            );
            assert_eq!(got.face_verts(), want.face_verts());
            assert_eq!(
                got.knots, want.knots,
                "pose {pose}: refined intervals and weights"
            );
        }
    }
    assert!(matches!(
        subsurf::Reposer::new(&bishop, &opts),
        Err(subsurf::Error::Nurss(
            nonuniform::NurssError::SemiSharp { .. }
        ))
    ));
}

fn load(name: &str) -> (PolyMesh, Options) {
    let obj = read_obj(&osd_shapes_dir().join(format!("{name}.obj"))).expect("read shape");
    (obj.mesh, obj.options.resolve(Options::default()))
}

/// Large levels are built and applied in parallel: the result must not depend on the
/// number of threads, and must still agree with `subdivide`.
#[test]
fn parallel_plan_is_deterministic_and_exact() {
    let (mesh, options) = load("catmark_bishop");
    let levels = 4;
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let plan1 =
        pool(1).install(|| RefinePlan::new(&mesh, Scheme::CatmullClark, options, levels).unwrap());
    let plan2 =
        pool(2).install(|| RefinePlan::new(&mesh, Scheme::CatmullClark, options, levels).unwrap());
    let moved = deform(mesh.positions());
    let a = pool(1).install(|| plan1.apply(&moved));
    let b = pool(2).install(|| plan2.apply(&moved));
    let c = pool(2).install(|| plan1.apply(&moved));
    assert!(a.iter().zip(&b).all(|(x, y)| x == y));
    assert!(a.iter().zip(&c).all(|(x, y)| x == y));
    assert_eq!(plan1.num_weights(), plan2.num_weights());

    let mut m = mesh.clone();
    m.positions_mut().copy_from_slice(&moved);
    let want = subdivided(&m, options, levels);
    let (d, at) = max_diff(&a, &want);
    let tol = REL_TOL * diagonal(&moved);
    assert!(d <= tol, "vertex {at} differs by {d:e} (tolerance {tol:e})");
}

/// `apply_into` re-uses its buffers from frame to frame and gives what `apply` gives.
#[test]
fn apply_into_reuses_buffers() {
    let (mesh, options) = load("catmark_pawn");
    let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, 3).unwrap();
    let mut out = Vec::new();
    let mut scratch = PlanScratch::default();
    let mut pos = mesh.positions().to_vec();
    for frame in 0..4 {
        for (i, p) in pos.iter_mut().enumerate() {
            p[1] += 0.01 * (frame as f64 + i as f64).sin();
        }
        plan.apply_into(&pos, &mut out, &mut scratch);
        let fresh = plan.apply(&pos);
        assert_eq!(out.len(), plan.num_vertices());
        assert!(out.iter().zip(&fresh).all(|(x, y)| x == y));
    }
}

/// Any primvar, not only positions: constants stay constant (partition of unity), and a
/// level-0 plan is the identity.
#[test]
fn primvars_and_level_zero() {
    let (mesh, options) = load("catmark_chaikin1");
    let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, 2).unwrap();
    let ones = vec![[1.0]; mesh.num_vertices()];
    for x in plan.apply(&ones) {
        assert!((x[0] - 1.0).abs() < 1e-14);
    }
    let id = RefinePlan::new(&mesh, Scheme::CatmullClark, options, 0).unwrap();
    assert_eq!(id.num_vertices(), mesh.num_vertices());
    assert_eq!(id.apply(mesh.positions()), mesh.positions());
    assert_eq!(id.num_weights(), 0);
}

/// Values of any width go through the regular patches too (positions use a vectorised
/// kernel where the processor allows, other widths the portable one): each component
/// comes out as the positions do, to rounding.
#[test]
fn patches_for_any_width() {
    let (mesh, options) = load("catmark_pawn");
    let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, 4).unwrap();
    assert!(plan.num_patches() > 0);
    let pos = deform(mesh.positions());
    let want = plan.apply(&pos);
    let tol = 1e-15 * diagonal(&pos);
    let four: Vec<[f64; 4]> = pos.iter().map(|p| [p[0], p[1], p[2], 1.0]).collect();
    let seven: Vec<[f64; 7]> = pos
        .iter()
        .map(|p| [p[2], p[1], p[0], 1.0, p[0], p[1], p[2]])
        .collect();
    let got4 = plan.apply(&four);
    let got7 = plan.apply(&seven);
    for (i, w) in want.iter().enumerate() {
        let (a, b) = (got4[i], got7[i]);
        for k in 0..3 {
            assert!((a[k] - w[k]).abs() <= tol, "vertex {i}: {a:?} vs {w:?}");
            assert!((b[4 + k] - w[k]).abs() <= tol, "vertex {i}: {b:?} vs {w:?}");
            assert!((b[2 - k] - w[k]).abs() <= tol, "vertex {i}: {b:?} vs {w:?}");
        }
        assert!((a[3] - 1.0).abs() < 1e-14 && (b[3] - 1.0).abs() < 1e-14);
    }
}

/// The estimate a caller checks before building errs high, and grows with the output.
#[test]
fn memory_estimate_covers_the_plan() {
    let options = Options::default();
    // Quads, and triangles (whose ring patches refine four levels at once at level 4).
    for mesh in [load("catmark_pawn").0, scrambled_triangle_torus(12)] {
        for levels in 1..=4 {
            let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, levels).unwrap();
            let estimate = RefinePlan::estimate_memory(&mesh, Scheme::CatmullClark, levels);
            let output = (24 * plan.num_vertices()) as u64;
            assert!(
                estimate > plan.memory_bytes() as u64 + output,
                "level {levels}"
            );
            assert!(
                RefinePlan::estimate_memory(&mesh, Scheme::CatmullClark, levels + 1) > 3 * estimate
            );
        }
        assert_eq!(
            RefinePlan::estimate_memory(&mesh, Scheme::CatmullClark, 40),
            u64::MAX
        );
    }
}

#[test]
#[should_panic(expected = "base values")]
fn wrong_base_length_panics() {
    let (mesh, options) = load("catmark_cube");
    let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, 1).unwrap();
    plan.apply(&mesh.positions()[1..]);
}

/// A torus of `2 n²` triangles with random edge flips (a fixed xorshift sequence): vertex
/// valences from 4 to about 12, as in a scanned surface, so that its triangles have
/// about a hundred rings of different shapes (keys of the ring patches).
fn scrambled_triangle_torus(n: u32) -> PolyMesh {
    use std::collections::HashMap;
    let (big, small) = (3.0, 1.0);
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (
                std::f64::consts::TAU * f64::from(i) / f64::from(n),
                std::f64::consts::TAU * f64::from(j) / f64::from(n),
            );
            let r = big + small * v.cos();
            positions.push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let at = |i: u32, j: u32| (i % n) * n + j % n;
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let [a, b, c, d] = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
            faces.extend([[a, b, c], [a, c, d]]);
        }
    }
    // The face on the left of each directed edge, and each vertex's valence.
    let mut left: HashMap<(u32, u32), usize> = HashMap::new();
    for (f, t) in faces.iter().enumerate() {
        for k in 0..3 {
            left.insert((t[k], t[(k + 1) % 3]), f);
        }
    }
    let mut valence = vec![6u32; positions.len()];
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    for _ in 0..4 * faces.len() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let f = (state % faces.len() as u64) as usize;
        let k = (state >> 32) as usize % 3;
        // Edge (a, b) of f = (a, b, c), with g = (b, a, d) across it, becomes (c, d).
        let [a, b, c] = [0, 1, 2].map(|i| faces[f][(k + i) % 3]);
        let g = left[&(b, a)];
        let d = (faces[g].iter().copied())
            .find(|&x| x != a && x != b)
            .expect("triangle");
        if left.contains_key(&(c, d)) || valence[a as usize] <= 4 || valence[b as usize] <= 4 {
            continue;
        }
        for t in [faces[f], faces[g]] {
            for k in 0..3 {
                left.remove(&(t[k], t[(k + 1) % 3]));
            }
        }
        faces[f] = [a, d, c];
        faces[g] = [b, c, d];
        for h in [f, g] {
            let t = faces[h];
            for k in 0..3 {
                left.insert((t[k], t[(k + 1) % 3]), h);
            }
        }
        valence[a as usize] -= 1;
        valence[b as usize] -= 1;
        valence[c as usize] += 1;
        valence[d as usize] += 1;
    }
    PolyMesh::from_faces(positions, &faces).expect("torus")
}

/// An irregular triangulation with many ring shapes and more faces than one unit of
/// parallel work (its ring patches are applied by units of several runs of faces, each
/// shape's patches of a unit together): the plan agrees with `subdivide`, on one thread
/// and on two, bit for bit between them.
#[test]
fn many_ring_shapes_in_units_of_several_runs() {
    let mesh = scrambled_triangle_torus(48);
    let options = Options::default();
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let moved = deform(mesh.positions());
    let mut m = mesh.clone();
    m.positions_mut().copy_from_slice(&moved);
    for levels in [3, 4] {
        let plan = RefinePlan::new(&mesh, Scheme::CatmullClark, options, levels).unwrap();
        assert!(plan.num_patches() > 4000);
        let a = pool(1).install(|| plan.apply(&moved));
        let b = pool(2).install(|| plan.apply(&moved));
        assert!(a.iter().zip(&b).all(|(x, y)| x == y));
        let want = subdivided(&m, options, levels);
        let (d, at) = max_diff(&a, &want);
        let tol = REL_TOL * diagonal(&moved);
        assert!(
            d <= tol,
            "level {levels}: vertex {at} differs by {d:e} ({tol:e})"
        );
    }
}

/// `Reposer` with the limit gives `subdivide`'s limit positions and normals on every
/// regression shape at levels 0–2 (the shapes' own positions and moved ones): positions
/// within `1e-14 ×` the diagonal, normals within 1e-9. The plan's level positions differ
/// from a refinement's by rounding, so this holds only because normals take tangents that
/// cancel to rounding noise for parallel (`limit::normals`): on the non-manifold and
/// valence-2 shapes, exact tests gave normals of noise, in any direction.
///
/// The same for mixed subdivision, `Reposer::new` against `subdivide`, both with `Scheme::Adjustable` (`c =
/// 0.3` on the first level; at level 0 the limit is Catmull-Clark's, and on shapes with
/// faces other than quads the plan then refines one Catmull-Clark level for the limit
/// masks).
#[test]
fn reposer_limit_equals_subdivide_on_all_shapes() {
    let mixed = Mixed {
        scheme: Adjustable::new(0.3).expect("c in [0, 1]"),
        steps: 1,
    };
    let mut failures = Vec::new();
    let mut cases = 0;
    for (name, mesh, options) in osd_shapes() {
        let mut moved = mesh.clone();
        moved
            .positions_mut()
            .copy_from_slice(&deform(mesh.positions()));
        for (levels, mixed) in (0..=2).flat_map(|l| [(l, None), (l, Some(mixed))]) {
            let opts = SubdivideOptions {
                levels,
                options,
                limit: true,
                ..SubdivideOptions::default()
            };
            let mut reposer = match mixed {
                Some(m) => subsurf::Reposer::new(
                    &mesh,
                    &SubdivideOptions {
                        scheme: Scheme::Adjustable(m),
                        ..opts.clone()
                    },
                ),
                None => subsurf::Reposer::new(&mesh, &opts),
            }
            .expect("reposer");
            for (what, m) in [("moved", &moved), ("original", &mesh)] {
                let want = match mixed {
                    Some(mixed) => subdivide(
                        m,
                        &SubdivideOptions {
                            scheme: Scheme::Adjustable(mixed),
                            ..opts.clone()
                        },
                    ),
                    None => subdivide(m, &opts),
                }
                .expect("subdivide");
                let got = reposer
                    .pose(m.positions())
                    .expect("pose")
                    .positions()
                    .to_vec();
                let tol = REL_TOL * diagonal(m.positions());
                let (d, at) = max_diff(&got, want.mesh.positions());
                if d > tol || d.is_nan() {
                    failures.push(format!(
                        "{name} level {levels} {what} {mixed:?}: vertex {at} differs by {d:e}"
                    ));
                }
                let normals = reposer.normals().expect("normals");
                let (d, at) = max_diff(normals, want.normals.as_deref().expect("normals"));
                if d > 1e-9 || d.is_nan() {
                    failures.push(format!(
                        "{name} level {levels} {what} {mixed:?}: normal {at} differs by {d:e}"
                    ));
                }
                cases += 1;
            }
        }
    }
    assert!(cases >= 960, "{cases} cases");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Loop and bilinear plans (sparse rows on every level) equal `subdivide` with the same
/// scheme, index for index, within `1e-14 ×` the diagonal: Loop on its regression shapes at
/// levels 1–4, bilinear on its own and on every Catmull-Clark shape (n-gons, holes,
/// non-manifold) at levels 1–3; on the shapes' positions and moved ones. `Reposer` with
/// the limit (levels 0–2) gives `subdivide`'s limit positions (1e-14) and normals (1e-9).
#[test]
fn loop_and_bilinear_plans_equal_subdivide() {
    let loop_shapes = osd_shapes_of("loop_")
        .into_iter()
        .map(|s| (Scheme::Loop, 4, s));
    let bilinear_shapes = osd_shapes_of("bilinear_")
        .into_iter()
        .chain(osd_shapes())
        .map(|s| (Scheme::Bilinear, 3, s));
    let mut failures = Vec::new();
    let (mut cases, mut limit_cases) = (0, 0);
    let mut check = |what: String, got: &[[f64; 3]], want: &[[f64; 3]], tol: f64| {
        if got.len() != want.len() {
            failures.push(format!(
                "{what}: {} values, {} wanted",
                got.len(),
                want.len()
            ));
            return;
        }
        let (d, at) = max_diff(got, want);
        if d > tol || d.is_nan() {
            failures.push(format!(
                "{what}: value {at} differs by {d:e} (tolerance {tol:e})"
            ));
        }
    };
    for (scheme, max_level, (name, mesh, options)) in loop_shapes.chain(bilinear_shapes) {
        let mut moved = mesh.clone();
        moved
            .positions_mut()
            .copy_from_slice(&deform(mesh.positions()));
        for levels in 0..=max_level {
            let opts = SubdivideOptions {
                levels,
                options,
                scheme,
                ..SubdivideOptions::default()
            };
            let plan = RefinePlan::new(&mesh, scheme, options, levels).expect("plan");
            let limit_opts = SubdivideOptions {
                limit: true,
                ..opts.clone()
            };
            let mut reposer =
                (levels <= 2).then(|| subsurf::Reposer::new(&mesh, &limit_opts).expect("reposer"));
            for (which, m) in [("original", &mesh), ("moved", &moved)] {
                let tol = REL_TOL * diagonal(m.positions());
                let case = format!("{scheme} {name} level {levels} {which}");
                let want = subdivide(m, &opts).expect("subdivide");
                check(
                    case.clone(),
                    &plan.apply(m.positions()),
                    want.mesh.positions(),
                    tol,
                );
                cases += 1;
                if let Some(r) = reposer.as_mut() {
                    let want = subdivide(m, &limit_opts).expect("subdivide --limit");
                    let got = r.pose(m.positions()).expect("pose").positions().to_vec();
                    check(format!("{case} limit"), &got, want.mesh.positions(), tol);
                    let normals = r.normals().expect("normals");
                    let want_n = want.normals.as_deref().expect("normals");
                    check(format!("{case} normals"), normals, want_n, 1e-9);
                    limit_cases += 1;
                }
            }
        }
    }
    assert!(cases >= 2 * (25 * 5 + 90 * 4), "{cases} cases");
    assert!(limit_cases >= 2 * 3 * 115, "{limit_cases} limit cases");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `mesh` with random tags from `seed`: about a third of its edges semi-sharp (0.5 to 3)
/// or infinitely sharp, three sharp corners and two holes.
fn with_random_tags(mesh: &PolyMesh, seed: u64) -> PolyMesh {
    let mut rng = Rng(seed | 1);
    let mut m = mesh.clone();
    let mut edges: Vec<[u32; 2]> = (m.faces())
        .flat_map(|f| (0..f.len()).map(move |k| [f[k], f[(k + 1) % f.len()]]))
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    for [v0, v1] in edges {
        if rng.next() < 0.35 {
            // A few values, as modelled creases have (a face's ring matrix is shared
            // by the faces with the same sharpness around the same shape).
            let values = [0.5, 1.0, 1.5, 2.0, 3.0, SHARPNESS_INFINITE];
            let sharpness = values[(rng.next() * values.len() as f64) as usize % values.len()];
            m.tags
                .creases
                .push(subsurf::mesh::Crease { v0, v1, sharpness });
        }
    }
    let (nv, nf) = (m.num_vertices() as f64, m.num_faces() as f64);
    for sharpness in [0.6, 2.5, SHARPNESS_INFINITE] {
        let vertex = (rng.next() * nv) as u32;
        m.tags
            .corners
            .push(subsurf::mesh::Corner { vertex, sharpness });
    }
    m.tags.holes = vec![(rng.next() * nf) as u32, (rng.next() * nf) as u32];
    m
}

/// Loop's ring patches and bilinear's face patches (the last levels of their plans)
/// re-pose an all-triangle mesh with random semi-sharp and infinitely sharp creases,
/// corners and holes as `subdivide` refines it, in each boundary mode and with both
/// crease rules, within `1e-14 ×` the diagonal at levels 1–4; and the kernels are used:
/// they compute most vertices, and every vertex of a regular all-triangle torus, whose
/// plan then stores no sparse weight.
#[test]
fn loop_and_bilinear_kernels_equal_subdivide_with_random_tags() {
    let bishop = read_obj(&osd_shapes_dir().join("catmark_bishop.obj")).expect("bishop");
    let mut tris: Vec<[u32; 3]> = Vec::new();
    for f in bishop.mesh.faces() {
        for k in 1..f.len() - 1 {
            tris.push([f[0], f[k], f[k + 1]]);
        }
    }
    let pos = bishop.mesh.positions();
    // The triangles below a cut: an open mesh, its boundary along the cut.
    let open: Vec<[u32; 3]> = (tris.iter().copied())
        .filter(|t| t.iter().map(|&v| pos[v as usize][2]).sum::<f64>() < 3.0 * 0.6)
        .collect();
    let open = PolyMesh::from_faces(pos.to_vec(), &open).expect("open bishop");
    let mut failures = Vec::new();
    for (seed, scheme) in [(5, Scheme::Loop), (9, Scheme::Loop), (13, Scheme::Bilinear)] {
        let mesh = with_random_tags(&open, seed);
        let tol = REL_TOL * diagonal(mesh.positions());
        for boundary in ["edge-only", "edge-and-corner", "none"] {
            for crease_method in ["uniform", "chaikin"] {
                let options = Options {
                    boundary: boundary.parse().expect("mode"),
                    crease_method: crease_method.parse().expect("method"),
                    ..Options::default()
                };
                for levels in 1..=4 {
                    let plan = RefinePlan::new(&mesh, scheme, options, levels).expect("plan");
                    let opts = SubdivideOptions {
                        levels,
                        options,
                        scheme,
                        ..SubdivideOptions::default()
                    };
                    let want = subdivide(&mesh, &opts).expect("subdivide");
                    let got = plan.apply(mesh.positions());
                    let (d, at) = max_diff(&got, want.mesh.positions());
                    let case =
                        format!("{scheme} seed {seed} {boundary} {crease_method} level {levels}");
                    if d > tol || d.is_nan() {
                        failures.push(format!("{case}: value {at} differs by {d:e}"));
                    }
                    // Kernels from level 3 on; at level 4, most of the output (a sparse
                    // row has several weights). On the base mesh nearly every ring here
                    // is unique (a third of the edges carry one of six sharpness values)
                    // and a ring seen on fewer than four faces is left to the rows.
                    let rows_only = levels >= 3 && plan.num_patches() == 0;
                    if rows_only || levels == 4 && plan.num_weights() > got.len() {
                        failures.push(format!("{case}: {} weights", plan.num_weights()));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));

    // A regular torus: 16 × 12 squares, each cut along the same diagonal.
    let (n, m) = (16u32, 12u32);
    let id = |i: u32, j: u32| (i % n) * m + j % m;
    let torus_pos: Vec<[f64; 3]> = (0..n * m)
        .map(|k| {
            let (u, v) = (
                std::f64::consts::TAU * f64::from(k / m) / f64::from(n),
                std::f64::consts::TAU * f64::from(k % m) / f64::from(m),
            );
            let r = 1.0 + 0.3 * v.cos();
            [r * u.cos(), r * u.sin(), 0.3 * v.sin()]
        })
        .collect();
    let torus_faces: Vec<[u32; 3]> = (0..n * m)
        .flat_map(|k| {
            let (i, j) = (k / m, k % m);
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            [[a, b, c], [a, c, d]]
        })
        .collect();
    let torus = PolyMesh::from_faces(torus_pos, &torus_faces).expect("torus");
    for levels in 2..=3 {
        let plan = RefinePlan::new(&torus, Scheme::Loop, Options::default(), levels).expect("plan");
        assert_eq!(plan.num_weights(), 0, "level {levels}");
        assert_eq!(plan.num_patches(), torus_faces.len(), "level {levels}");
        let opts = SubdivideOptions {
            levels,
            scheme: Scheme::Loop,
            ..SubdivideOptions::default()
        };
        let want = subdivide(&torus, &opts).expect("subdivide");
        let (d, at) = max_diff(&plan.apply(torus.positions()), want.mesh.positions());
        assert!(
            d <= REL_TOL * diagonal(torus.positions()),
            "level {levels}: value {at} differs by {d:e}"
        );
    }
}
