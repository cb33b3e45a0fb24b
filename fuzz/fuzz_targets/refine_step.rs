//! Parse a small mesh, then one Catmull-Clark step (`subdivide`, level 1), with and without
//! limit positions and normals, keeping or dropping holes.
//!
//! Checks: no panic; `subdivide` accepts every mesh the reader accepts; the result is a
//! valid all-quad mesh with at most one quad per input face corner and at most V + E + F
//! vertices; positions and normals are finite when the input coordinates are moderate.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::parse_obj;
use subsurf::mesh::{Options, Topology};
use subsurf::{subdivide, SubdivideOptions};

/// Caps that keep one execution in the milliseconds.
const MAX_VERTICES: usize = 2000;
const MAX_FACES: usize = 2000;
const MAX_CORNERS: usize = 8000;
/// The reader rejects larger coordinates (`subsurf::mesh::MAX_COORDINATE`, 1e75), so every
/// accepted mesh is "moderate"; the check stays in case that limit is ever raised.
const MODERATE: f64 = 1e100;

fuzz_target!(|data: &[u8]| {
    let Ok(obj) = parse_obj(data, "fuzz.obj") else {
        return;
    };
    let mesh = &obj.mesh;
    if mesh.num_vertices() > MAX_VERTICES
        || mesh.num_faces() > MAX_FACES
        || mesh.face_verts().len() > MAX_CORNERS
    {
        return;
    }
    let scheme = obj.options.resolve(Options::default());
    let moderate = mesh
        .positions()
        .iter()
        .flatten()
        .all(|x| x.abs() <= MODERATE);
    let Ok((base, _)) = Topology::from_mesh(mesh, &scheme) else {
        return;
    };
    for (limit, keep_holes) in [(false, false), (true, true)] {
        let opts = SubdivideOptions {
            levels: 1,
            scheme,
            limit,
            keep_holes,
            max_memory: None,
        };
        let out = match subdivide(mesh, &opts) {
            Ok(out) => out,
            Err(e) => panic!("subdivide rejects a mesh the reader accepted: {e}"),
        };
        let m = &out.mesh;
        if moderate {
            // (Before coordinates were capped at 1e75, ones near f64::MAX overflowed here:
            // fuzz/regressions/refine_step.)
            m.validate().expect("subdivide returned an invalid mesh");
        }
        assert!(
            m.faces().all(|f| f.len() == 4),
            "a level-1 face is not a quad"
        );
        assert!(m.num_faces() <= mesh.face_verts().len());
        assert!(m.num_vertices() <= base.num_vertices() + base.num_edges() + base.num_faces());
        if moderate {
            assert!(
                m.positions().iter().flatten().all(|x| x.is_finite()),
                "non-finite refined position from moderate input"
            );
            if let Some(n) = &out.normals {
                assert_eq!(n.len(), m.num_vertices());
                assert!(
                    n.iter().flatten().all(|x| x.is_finite()),
                    "non-finite normal"
                );
            }
        }
    }
});
