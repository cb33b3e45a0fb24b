//! G2 caps on the mixed (shape-adjustable) surface ([Tang et al. 2017]): `k` steps of the
//! adjustable scheme with parameter `c`, then Catmull-Clark, with a G2 cap at every
//! extraordinary vertex. With `c = ½` it is the Catmull-Clark G2 surface; for other `c`
//! the caps join the mixed surface G2 (the same bounds as the Catmull-Clark caps), and
//! away from the caps the surface is the mixed surface.

use subsurf::g2cap::{continuity_report, DenseCapSolver, G2Surface, G2SurfaceOptions};
use subsurf::limit::SurfacePoint;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::scheme::Adjustable;
use subsurf::{Mixed, MixedSurface, Scheme};

use crate::common;
use common::{cube, double_cone, example};

fn mixed(c: f64, steps: u32) -> Mixed {
    Mixed {
        scheme: Adjustable::new(c).unwrap(),
        steps,
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

/// Sample points of every (sub-)face of `mesh`, on a 9×9 grid including the edges.
fn samples(mesh: &PolyMesh) -> Vec<SurfacePoint> {
    let mut out = Vec::new();
    for f in 0..mesh.num_faces() {
        let m = mesh.face(f).len();
        let subfaces = if m == 4 { 1 } else { m };
        for s in 0..subfaces {
            for i in 0..=8 {
                for j in 0..=8 {
                    out.push(SurfacePoint {
                        face: f as u32,
                        subface: s as u32,
                        u: i as f64 / 8.0,
                        v: j as f64 / 8.0,
                    });
                }
            }
        }
    }
    out
}

/// The largest difference of cap control points and of positions at the sample points.
fn difference(a: &G2Surface, b: &G2Surface, mesh: &PolyMesh, what: &str) -> f64 {
    assert_eq!(a.levels(), b.levels(), "{what}");
    assert_eq!(a.caps().len(), b.caps().len(), "{what}");
    assert_eq!(a.uncapped(), b.uncapped(), "{what}");
    let mut worst = 0.0f64;
    for (x, y) in a.caps().iter().zip(b.caps()) {
        assert_eq!(
            (x.vertex, x.face_centre),
            (y.vertex, y.face_centre),
            "{what}"
        );
        assert_eq!(x.slots, y.slots, "{what}");
        for (pa, pb) in x.cap.patches().iter().zip(y.cap.patches()) {
            for (p, q) in pa.points().iter().zip(pb.points()) {
                worst = worst.max(dist(*p, *q));
            }
        }
    }
    for p in samples(mesh) {
        worst = worst.max(dist(a.eval_point(p).unwrap().p, b.eval_point(p).unwrap().p));
    }
    worst
}

/// `c = ½` is Catmull-Clark: the mixed surface equals the Catmull-Clark limit surface
/// (checked here independently of the caps), and its G2 surface is the Catmull-Clark G2
/// surface — the same caps and values, to 1e-12 — for one and two adjustable steps.
#[test]
fn c_one_half_is_the_catmull_clark_g2_surface() {
    for (what, mesh) in [
        ("cube", cube()),
        ("double cone 5", double_cone(5, 8)),
        ("hut (n-gons)", example("hut.obj")),
    ] {
        let opts = G2SurfaceOptions::default();
        let cc = G2Surface::new(&mesh, &opts).unwrap();
        assert!(!cc.caps().is_empty(), "{what}");
        for k in [1, 2] {
            let reference = MixedSurface::new(&mesh, Options::default(), mixed(0.5, k)).unwrap();
            for p in samples(&mesh) {
                let (a, b) = (
                    reference.eval_point(p).unwrap(),
                    cc.limit().eval_point(p).unwrap(),
                );
                assert!(dist(a.p, b.p) <= 1e-14, "{what}, k = {k}, {p:?}");
            }
            let half = G2Surface::new(
                &mesh,
                &G2SurfaceOptions {
                    scheme: Scheme::Adjustable(mixed(0.5, k)),
                    ..opts
                },
            )
            .unwrap();
            let d = difference(&cc, &half, &mesh, what);
            assert!(d <= 1e-12, "{what}, k = {k}: {d:e}");
        }
    }
}

/// As `c → ½` the G2 surface of the mixed surface (built through the refined mesh) tends
/// to the Catmull-Clark G2 surface: at `c = ½ ± 10⁻¹²` they differ only by the rounding
/// amplified by the cap solve (measured `~3·10⁻¹³`), and at `c = 0.45` visibly.
#[test]
fn caps_tend_to_the_catmull_clark_caps_as_c_tends_to_one_half() {
    let mesh = double_cone(5, 8);
    let opts = G2SurfaceOptions::default();
    let cc = G2Surface::new(&mesh, &opts).unwrap();
    for c in [0.5 - 1e-12, 0.5 + 1e-12] {
        let near = G2Surface::new(
            &mesh,
            &G2SurfaceOptions {
                scheme: Scheme::Adjustable(mixed(c, 1)),
                ..opts
            },
        )
        .unwrap();
        assert!(near.mixed().is_some());
        let d = difference(&cc, &near, &mesh, "near ½");
        eprintln!("c = {c}: largest difference {d:e}");
        assert!(d <= 1e-12, "c = {c}: {d:e}");
    }
    let far = G2Surface::new(
        &mesh,
        &G2SurfaceOptions {
            scheme: Scheme::Adjustable(mixed(0.45, 1)),
            ..opts
        },
    )
    .unwrap();
    assert!(difference(&cc, &far, &mesh, "c = 0.45") > 1e-3);
}

/// For `c = 0.3` and `0.7` (one and two adjustable steps) every extraordinary vertex of
/// the cube (valence 3) and of a mesh with valence-5 poles is capped, and the caps join
/// each other and the mixed surface G2: position gap ≤ 1e-10 (of the size), normal angle
/// ≤ 1e-8 rad, relative normal-curvature jump ≤ 1e-6, at 20 points per boundary, and one
/// second fundamental form at the vertex — where the uncapped mixed surface has the
/// curvature defect of Catmull-Clark.
#[test]
fn caps_join_the_mixed_surface_g2() {
    for (what, mesh, caps) in [
        ("cube", cube(), 8),
        ("double cone 5", double_cone(5, 8), 2 + 2 * 5),
    ] {
        for (c, k) in [(0.3, 1), (0.7, 1), (0.3, 2)] {
            let what = format!("{what}, c = {c}, k = {k}");
            let s = G2Surface::new(
                &mesh,
                &G2SurfaceOptions {
                    scheme: Scheme::Adjustable(mixed(c, k)),
                    ..G2SurfaceOptions::default()
                },
            )
            .unwrap();
            assert_eq!(s.levels(), 2.max(k + 1), "{what}");
            assert!(s.uncapped().is_empty(), "{what}: {:?}", s.uncapped());
            assert_eq!(s.caps().len(), caps, "{what}");
            let r = continuity_report(&s, 20).unwrap();
            eprintln!("{what}:\n{r}");
            let size = s.size();
            for row in [&r.g2_inner, &r.g2_outer] {
                assert!(row.max_gap <= 1e-10 * size.max(1.0), "{what}: {r}");
                assert!(row.max_normal_angle <= 1e-8, "{what}: {r}");
                assert!(row.max_curvature_jump <= 1e-6, "{what}: {r}");
            }
            assert!(r.g2_vertex.max_normal_angle <= 1e-8, "{what}: {r}");
            assert!(r.g2_vertex.max_curvature_jump <= 1e-6, "{what}: {r}");
            assert!(r.cc_inner.max_normal_angle <= 1e-8, "{what}: {r}");
            assert!(r.cc_vertex.max_curvature_jump >= 1e-2, "{what}: {r}");
        }
    }
}

/// Away from the caps the G2 surface is the mixed surface (built independently here), to
/// 1e-12 in position and derivatives; inside the caps it differs from it (slightly), and
/// the caps depend on `c`.
#[test]
fn outside_the_caps_it_is_the_mixed_surface() {
    let mesh = double_cone(5, 8);
    let opts = G2SurfaceOptions::default();
    let half = G2Surface::new(&mesh, &opts).unwrap();
    for c in [0.3, 0.7] {
        let m = mixed(c, 1);
        let s = G2Surface::new(
            &mesh,
            &G2SurfaceOptions {
                scheme: Scheme::Adjustable(m),
                ..opts
            },
        )
        .unwrap();
        let reference = MixedSurface::new(&mesh, Options::default(), m).unwrap();
        let (mut outside, mut inside) = (0, 0);
        let mut from_half = 0.0f64;
        for p in samples(&mesh) {
            let a = s.eval_point(p).unwrap();
            let b = reference.eval_point(p).unwrap();
            if s.locate(p).is_some() {
                inside += 1;
                assert!(dist(a.p, b.p) < 0.05, "{p:?}");
                from_half = from_half.max(dist(a.p, half.eval_point(p).unwrap().p));
            } else {
                outside += 1;
                for (x, y) in [(a.p, b.p), (a.du, b.du), (a.dv, b.dv)] {
                    assert!(dist(x, y) <= 1e-12, "c = {c}, {p:?}: {x:?} vs {y:?}");
                }
                for (x, y) in [(a.duu, b.duu), (a.duv, b.duv), (a.dvv, b.dvv)] {
                    assert!(dist(x, y) <= 1e-12 * dist(y, [0.0; 3]).max(1.0), "{p:?}");
                }
            }
        }
        assert!(outside > 0 && inside > 0);
        assert!(
            from_half > 1e-3,
            "c = {c}: the caps ignore c ({from_half:e})"
        );
    }
}

/// Caps must lie inside one face of the c-refined mesh: a requested isolation level below
/// `k + 1` is raised (below it the neighbouring squares are not single bicubics for
/// `c ≠ ½`, and no vertex could be capped).
#[test]
fn isolation_level_is_at_least_steps_plus_one() {
    let opts = G2SurfaceOptions {
        levels: Some(2),
        ..Default::default()
    };
    let s = G2Surface::new(
        &cube(),
        &G2SurfaceOptions {
            scheme: Scheme::Adjustable(mixed(0.3, 3)),
            ..opts
        },
    )
    .unwrap();
    assert_eq!(s.levels(), 4);
    assert_eq!(s.caps().len(), 8);
    assert!(s.mixed().is_some());
}

/// On the mixed surface (`c ≠ ½`: other outer rows) the per-frequency caps are those of the
/// reference all-sectors solve, to 1e-9 of the surface's size (the reference's own rounding
/// error is up to ~4e-10).
#[test]
fn mixed_caps_are_the_all_sectors_solution() {
    let mesh = double_cone(5, 8);
    for (c, k) in [(0.3, 1), (0.7, 2)] {
        let s = G2Surface::new(
            &mesh,
            &G2SurfaceOptions {
                scheme: Scheme::Adjustable(mixed(c, k)),
                ..G2SurfaceOptions::default()
            },
        )
        .unwrap();
        let mut worst = 0.0f64;
        for info in s.caps() {
            let n = info.cap.valence();
            let ours: Vec<[f64; 3]> = info
                .cap
                .patches()
                .iter()
                .flat_map(|p| p.points().to_vec())
                .collect();
            let mut reference = ours.clone();
            DenseCapSolver::new(n)
                .unwrap()
                .complete(&mut reference)
                .unwrap();
            for (a, b) in ours.iter().zip(&reference) {
                worst = worst.max(dist(*a, *b));
            }
        }
        eprintln!("c = {c}, k = {k}: largest difference {worst:e}");
        assert!(worst <= 1e-9 * s.size(), "c = {c}: {worst:e}");
    }
}
