//! Parse a small mesh, build the exact limit surface (`LimitSurface::new`) and evaluate it
//! at points chosen by the input.
//!
//! Input layout: 16 bytes of parameters, then the OBJ text. The parameters are 4 points of
//! 4 bytes `[f, s, a, b]`: face `f` modulo the face count, sub-face `s` modulo the face's
//! sub-face count, `u` from bytes `(a, s)` and `v` from `(b, f)` (see [`param`]), quantised so
//! that corners and edges (u, v ∈ {0, ½, 1}) come up often: that is where the limit masks
//! and the eigen-analysis paths are.
//!
//! Checks: no panic; evaluation inside the domain of a face with a surface succeeds and is
//! finite (for moderate coordinates); out-of-domain and NaN parameters and bad face
//! indices are errors, not panics.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::parse_obj;
use subsurf::limit::{LimitSurface, SurfacePoint};
use subsurf::mesh::Options;

const MAX_VERTICES: usize = 400;
const MAX_FACES: usize = 200;
/// Derivatives must be finite below this magnitude. The reader rejects coordinates beyond
/// `subsurf::mesh::MAX_COORDINATE` (1e75), so this covers every accepted mesh. (A vertex at
/// 2e95 gave NaN derivatives before that cap: fuzz/regressions/limit_eval.)
const MODERATE: f64 = 1e75;

/// A parameter in [0, 1] from two bytes: 0 and 1 exactly for the extreme values, and the
/// dyadic and midpoint values that refinement boundaries sit on.
fn param(b: [u8; 2]) -> f64 {
    match b[0] {
        0..=31 => 0.0,
        32..=63 => 1.0,
        64..=79 => 0.5,
        80..=95 => f64::from(b[1] % 9) / 8.0,
        _ => f64::from(u16::from_le_bytes(b)) / 65535.0,
    }
}

fuzz_target!(|data: &[u8]| {
    if data.len() < 16 {
        return;
    }
    let (params, text) = data.split_at(16);
    let Ok(obj) = parse_obj(text, "fuzz.obj") else {
        return;
    };
    let mesh = &obj.mesh;
    if mesh.num_vertices() > MAX_VERTICES || mesh.num_faces() > MAX_FACES {
        return;
    }
    let options = obj.options.resolve(Options::default());
    let surface = match LimitSurface::new(mesh, options) {
        Ok(s) => s,
        Err(e) => panic!("LimitSurface rejects a mesh the reader accepted: {e}"),
    };
    assert_eq!(surface.num_faces(), mesh.num_faces());
    let moderate = mesh
        .positions()
        .iter()
        .flatten()
        .all(|x| x.abs() <= MODERATE);
    let mut points = Vec::new();
    for c in params.chunks_exact(4) {
        if surface.num_faces() == 0 {
            break;
        }
        let face = usize::from(c[0]) % surface.num_faces();
        let subface = usize::from(c[1]) % surface.num_subfaces(face).max(1);
        let p = SurfacePoint {
            face: face as u32,
            subface: subface as u32,
            u: param([c[2], c[1]]),
            v: param([c[3], c[0]]),
        };
        points.push(p);
        match surface.eval_point(p) {
            Ok(d) => {
                if moderate {
                    let mut all = d.p.iter().chain(&d.du).chain(&d.dv);
                    assert!(
                        all.all(|x| x.is_finite()),
                        "non-finite limit at {p:?}: {d:?}"
                    );
                }
            }
            Err(e) => assert!(
                !surface.has_surface(face),
                "eval failed on a face with a surface at {p:?}: {e}"
            ),
        }
    }
    // The batch interface agrees with one-at-a-time evaluation.
    let many = surface.eval_many(&points);
    for (p, r) in points.iter().zip(&many) {
        let one = surface.eval_point(*p);
        assert_eq!(one.is_ok(), r.is_ok());
        if let (Ok(a), Ok(b)) = (one, r) {
            assert_eq!(format!("{:?}", a.p), format!("{:?}", b.p));
        }
    }
    // Bad requests are errors.
    let n = surface.num_faces() as u32;
    assert!(surface.eval(n, 0.5, 0.5).is_err());
    if n > 0 {
        assert!(surface.eval(0, 1.5, 0.5).is_err());
        assert!(surface.eval(0, f64::NAN, 0.5).is_err());
        assert!(surface.eval(0, 0.5, -0.0).is_ok() || !surface.has_surface(0));
    }
});
