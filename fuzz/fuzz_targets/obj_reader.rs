//! `parse_obj` on arbitrary bytes (with tags, free-form statements, continuations, ...).
//!
//! Checks: no panic; an error names the source (`fuzz.obj:LINE: ...`); a parsed mesh is
//! valid, has one source line per face, and writing it with `write_obj` and reading it
//! back gives the same positions (bit for bit), faces and tags.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::{parse_obj, write_obj, WriteOptions};

fuzz_target!(|data: &[u8]| {
    let obj = match parse_obj(data, "fuzz.obj") {
        Ok(obj) => obj,
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("fuzz.obj"), "error without the file name: {msg}");
            assert!(!e.message.is_empty());
            return;
        }
    };
    let mesh = &obj.mesh;
    mesh.validate().expect("parse_obj returned an invalid mesh");
    assert_eq!(obj.face_lines.len(), mesh.num_faces());
    assert!(mesh.positions().iter().flatten().all(|x| x.is_finite()));

    let scheme = obj.options.resolve(Default::default());
    let opts = WriteOptions {
        scheme: Some(scheme),
        ..Default::default()
    };
    let mut text = Vec::new();
    write_obj(&mut text, mesh, &opts).expect("write_obj failed on a parsed mesh");
    let back = match parse_obj(&text, "written.obj") {
        Ok(b) => b,
        Err(e) => panic!("write_obj output does not read back: {e}"),
    };
    let bits = |p: &[[f64; 3]]| -> Vec<u64> { p.iter().flatten().map(|x| x.to_bits()).collect() };
    assert_eq!(bits(back.mesh.positions()), bits(mesh.positions()));
    assert_eq!(back.mesh.face_offsets(), mesh.face_offsets());
    assert_eq!(back.mesh.face_verts(), mesh.face_verts());
    assert_eq!(back.mesh.tags.holes, mesh.tags.holes);
    assert_eq!(back.mesh.tags.creases.len(), mesh.tags.creases.len());
    for (a, b) in back.mesh.tags.creases.iter().zip(&mesh.tags.creases) {
        assert_eq!((a.v0, a.v1, a.sharpness.to_bits()), (b.v0, b.v1, b.sharpness.to_bits()));
    }
    assert_eq!(back.mesh.tags.corners.len(), mesh.tags.corners.len());
    for (a, b) in back.mesh.tags.corners.iter().zip(&mesh.tags.corners) {
        assert_eq!((a.vertex, a.sharpness.to_bits()), (b.vertex, b.sharpness.to_bits()));
    }
    assert_eq!(back.options.resolve(Default::default()), scheme);
});
