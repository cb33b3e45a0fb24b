//! Parse, then build the topology (`Topology::from_mesh`) under every boundary mode, check
//! manifoldness (`check_manifold`, `PolyMesh::check_strict`) and summarise (`mesh_info`).
//!
//! Checks: no panic; adjacency is consistent (every edge's faces and every vertex's faces
//! contain it); `check_manifold` failing implies `check_strict` failing.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::parse_obj;
use subsurf::mesh::{BoundaryInterpolation, Options, Topology};

/// Larger inputs add time, not coverage.
const MAX_CORNERS: usize = 20_000;

fuzz_target!(|data: &[u8]| {
    let Ok(obj) = parse_obj(data, "fuzz.obj") else {
        return;
    };
    let mesh = &obj.mesh;
    if mesh.face_verts().len() > MAX_CORNERS {
        return;
    }
    let strict = mesh.check_strict();
    let file = obj.options.resolve(Options::default());
    for boundary in [
        None,
        Some(BoundaryInterpolation::None),
        Some(BoundaryInterpolation::EdgeAndCorner),
    ] {
        let options = Options {
            boundary: boundary.unwrap_or(file.boundary),
            ..file
        };
        let Ok((t, _warnings)) = Topology::from_mesh(mesh, &options) else {
            continue;
        };
        assert_eq!(t.num_vertices(), mesh.num_vertices());
        assert_eq!(t.num_faces(), mesh.num_faces());
        for f in 0..t.num_faces() {
            assert_eq!(t.face_vertices(f), mesh.face(f));
            assert_eq!(t.face_edge_list(f).len(), mesh.face(f).len());
        }
        for e in 0..t.num_edges() {
            for &f in t.edge_face_list(e) {
                assert!(t.face_edge_list(f as usize).contains(&(e as u32)));
            }
            let [a, b] = t.edge_vertices(e);
            assert!(t.vertex_edges(a as usize).contains(&(e as u32)));
            assert!(t.vertex_edges(b as usize).contains(&(e as u32)));
        }
        for v in 0..t.num_vertices() {
            for &f in t.vertex_faces(v) {
                assert!(t.face_vertices(f as usize).contains(&(v as u32)));
            }
        }
        if t.check_manifold().is_err() {
            assert!(
                strict.is_err(),
                "check_manifold fails but check_strict passes"
            );
        }
        let _ = subsurf::mesh_info(mesh, &options);
    }
});
