//! Limit stencil tables reproduce the exact evaluator: re-posing through the table equals
//! evaluating the moved mesh directly.

use subsurf::io::parse_obj;
use subsurf::limit::{LimitStencils, LimitSurface, SurfacePoint};
use subsurf::mesh::{Options, PolyMesh};

fn shape(name: &str) -> (PolyMesh, Options) {
    let path = format!("{}/tests/shapes/osd/{name}.obj", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&path).expect("shape file");
    let obj = parse_obj(&bytes, &path).expect("valid shape");
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

/// Every quad face, a 4×4 grid of parameters strictly inside and on the edges (corners of
/// irregular vertices included for positions).
fn samples(s: &LimitSurface) -> Vec<SurfacePoint> {
    let mut pts = Vec::new();
    for f in 0..s.num_faces() {
        if s.num_subfaces(f) != 1 || !s.has_surface(f) {
            continue;
        }
        for i in 0..4 {
            for j in 0..4 {
                let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
                pts.push(SurfacePoint {
                    face: f as u32,
                    subface: 0,
                    u,
                    v,
                });
            }
        }
    }
    pts
}

fn moved(mesh: &PolyMesh, t: f64) -> Vec<[f64; 3]> {
    mesh.positions()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let k = i as f64;
            [
                p[0] + t * (k * 0.37).sin(),
                p[1] + t * (k * 0.11).cos(),
                p[2] - t * (k * 0.23).sin(),
            ]
        })
        .collect()
}

#[test]
fn stencils_reproduce_the_evaluator_after_the_control_points_move() {
    for name in [
        "catmark_cube",
        "catmark_torus",
        "catmark_pole8",
        "catmark_cube_creases1",
        "catmark_edgecorner",
    ] {
        let (mesh, options) = shape(name);
        let surface = LimitSurface::new(&mesh, options).expect("surface");
        let pts = samples(&surface);
        let table = LimitStencils::new(&mesh, options, &pts).expect("stencils");
        assert_eq!(table.len(), pts.len());
        let new_pos = moved(&mesh, 0.1);
        let mut moved_mesh = mesh.clone();
        moved_mesh.positions_mut().copy_from_slice(&new_pos);
        let direct = LimitSurface::new(&moved_mesh, options).expect("surface");
        let via_table = table.apply(&new_pos);
        for (p, d) in pts.iter().zip(&via_table) {
            let e = direct.eval_point(*p).expect("eval");
            let corner = (p.u == 0.0 || p.u == 1.0) && (p.v == 0.0 || p.v == 1.0);
            for k in 0..3 {
                assert!((e.p[k] - d.p[k]).abs() < 1e-12, "{name} {p:?} position");
                if !corner {
                    assert!((e.du[k] - d.du[k]).abs() < 1e-10, "{name} {p:?} du");
                    assert!((e.dv[k] - d.dv[k]).abs() < 1e-10, "{name} {p:?} dv");
                }
            }
        }
    }
}

/// Position weights form a partition of unity (affine invariance).
#[test]
fn position_weights_sum_to_one() {
    let (mesh, options) = shape("catmark_pawn");
    let surface = LimitSurface::new(&mesh, options).expect("surface");
    let pts: Vec<SurfacePoint> = samples(&surface).into_iter().step_by(7).collect();
    let table = LimitStencils::new(&mesh, options, &pts).expect("stencils");
    for (s, p) in pts.iter().enumerate() {
        let (sp, sd): (f64, f64) = table
            .stencil(s)
            .fold((0.0, 0.0), |a, (_, w)| (a.0 + w[0], a.1 + w[1]));
        assert!((sp - 1.0).abs() < 1e-12, "sample {s}: {sp}");
        let corner = (p.u == 0.0 || p.u == 1.0) && (p.v == 0.0 || p.v == 1.0);
        if !corner {
            assert!(sd.abs() < 1e-9, "sample {s}: du weights sum to {sd}");
        }
    }
}

#[test]
fn bad_samples_are_reported_by_index() {
    let (mesh, options) = shape("catmark_cube");
    let pts = [
        SurfacePoint {
            face: 0,
            subface: 0,
            u: 0.5,
            v: 0.5,
        },
        SurfacePoint {
            face: 99,
            subface: 0,
            u: 0.5,
            v: 0.5,
        },
    ];
    let e = LimitStencils::new(&mesh, options, &pts).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("sample 1: face 99 does not exist"),
        "{e}"
    );
}
