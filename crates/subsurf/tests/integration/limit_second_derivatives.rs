//! Second derivatives of the exact limit surface are the derivatives of its first
//! derivatives: central differences of `du`, `dv` agree with `duu`, `duv`, `dvv` on regular
//! and irregular faces alike (away from irregular corners, where the surface is not C²).

use subsurf::io::parse_obj;
use subsurf::limit::LimitSurface;
use subsurf::mesh::Options;

fn surface(name: &str) -> LimitSurface {
    let path = format!("{}/tests/shapes/osd/{name}.obj", env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(&path).expect("shape file");
    let obj = parse_obj(&bytes, &path).expect("valid shape");
    LimitSurface::new(&obj.mesh, obj.options.resolve(Options::default())).expect("surface")
}

#[test]
fn second_derivatives_match_differences_of_first_derivatives() {
    let h = 1e-5;
    for name in [
        "catmark_torus",
        "catmark_cube",
        "catmark_pole8",
        "catmark_tent_creases1",
        "catmark_single_crease",
    ] {
        let s = surface(name);
        for f in 0..s.num_faces().min(40) {
            if s.num_subfaces(f) != 1 || !s.has_surface(f) {
                continue;
            }
            for &(u, v) in &[(0.3, 0.4), (0.55, 0.7), (0.8, 0.2)] {
                let d = s.eval(f as u32, u, v).expect("eval");
                let du_p = s.eval(f as u32, u + h, v).expect("eval");
                let du_m = s.eval(f as u32, u - h, v).expect("eval");
                let dv_p = s.eval(f as u32, u, v + h).expect("eval");
                let dv_m = s.eval(f as u32, u, v - h).expect("eval");
                let scale =
                    d.du.iter()
                        .chain(&d.dv)
                        .fold(1e-3f64, |m, x| m.max(x.abs()));
                for k in 0..3 {
                    let duu = (du_p.du[k] - du_m.du[k]) / (2.0 * h);
                    let duv = (dv_p.du[k] - dv_m.du[k]) / (2.0 * h);
                    let dvu = (du_p.dv[k] - du_m.dv[k]) / (2.0 * h);
                    let dvv = (dv_p.dv[k] - dv_m.dv[k]) / (2.0 * h);
                    let tol = 1e-5 * scale;
                    assert!(
                        (duu - d.duu[k]).abs() < tol,
                        "{name} face {f} ({u},{v}) duu"
                    );
                    assert!(
                        (duv - d.duv[k]).abs() < tol,
                        "{name} face {f} ({u},{v}) duv"
                    );
                    assert!(
                        (dvu - d.duv[k]).abs() < tol,
                        "{name} face {f} ({u},{v}) dvu"
                    );
                    assert!(
                        (dvv - d.dvv[k]).abs() < tol,
                        "{name} face {f} ({u},{v}) dvv"
                    );
                }
            }
        }
    }
}
