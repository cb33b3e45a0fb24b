//! # A surface built for chosen faces is the full surface on those faces
//!
//! [`LimitSurface::builder`] can build some faces only
//! ([`SurfaceBuilder::faces`](subsurf::limit::SurfaceBuilder::faces)). On every OpenSubdiv
//! regression shape, with the scheme options of its tags, a surface of the quads only and
//! one of every third face must evaluate exactly (bit for bit: position, first and second
//! derivatives) as the surface of every face on each face they built, report no surface
//! on the others and refuse to evaluate them with `EvalError::NotBuilt`; a face count and
//! each face's number of sub-faces do not depend on the choice.

use subsurf::limit::{EvalError, LimitSurface, SurfacePoint};

use crate::common::osd_shapes;

/// Points of each sub-face evaluated: the corners, the middle and points off the axes.
const UV: [(f64, f64); 7] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (0.0, 1.0),
    (1.0, 1.0),
    (0.5, 0.5),
    (0.25, 0.8),
    (0.9, 0.15),
];

#[test]
fn chosen_faces_evaluate_as_in_the_full_surface_and_others_not_at_all() {
    let mut checked = [0usize; 2];
    for (name, mesh, options) in osd_shapes() {
        let full = LimitSurface::new(&mesh, options).expect("surface");
        let quads = |_: usize, verts: &[u32]| verts.len() == 4;
        let thirds = |f: usize, _: &[u32]| f % 3 == 1;
        for (choice, select) in [
            ("quads", &quads as &(dyn Fn(usize, &[u32]) -> bool + Sync)),
            ("every third", &thirds),
        ] {
            let some = LimitSurface::builder(&mesh, options)
                .faces(select)
                .build()
                .unwrap_or_else(|e| panic!("{name}, {choice}: {e}"));
            assert_eq!(some.num_faces(), full.num_faces(), "{name}");
            for f in 0..mesh.num_faces() {
                let chosen = select(f, mesh.face(f));
                let n = full.num_subfaces(f);
                assert_eq!(some.num_subfaces(f), n, "{name}, face {f}");
                assert_eq!(
                    some.has_surface(f),
                    chosen && full.has_surface(f),
                    "{name}, face {f}"
                );
                for subface in 0..n as u32 {
                    for (u, v) in UV {
                        let p = SurfacePoint {
                            face: f as u32,
                            subface,
                            u,
                            v,
                        };
                        let (a, b) = (some.eval_point(p), full.eval_point(p));
                        if chosen {
                            assert_eq!(a, b, "{name}, {choice}: face {f}.{subface} at ({u}, {v})");
                            checked[usize::from(b.is_ok())] += 1;
                        } else {
                            assert_eq!(
                                a,
                                Err(EvalError::NotBuilt { face: f as u32 }),
                                "{name}, face {f}"
                            );
                        }
                    }
                }
            }
        }
    }
    // Holes and faces without a surface are compared as errors; most points evaluate.
    assert!(
        checked[1] > 10 * checked[0] && checked[1] > 20_000,
        "{checked:?}"
    );
}
