//! `parse_ply` on arbitrary bytes (headers, the three encodings, lists, other elements).
//!
//! Checks: no panic; an error names the source (`fuzz.ply...`); a parsed mesh is valid,
//! finite, has one line per face for an ASCII body (none for a binary one), and writing it
//! with `write_ply` (binary little-endian) and reading it back gives the same positions (bit
//! for bit) and faces.
#![no_main]

use libfuzzer_sys::fuzz_target;
use subsurf::io::{parse_ply, write_ply, PlyEncoding};

fuzz_target!(|data: &[u8]| {
    let ply = match parse_ply(data, "fuzz.ply") {
        Ok(ply) => ply,
        Err(e) => {
            assert!(e.to_string().starts_with("fuzz.ply"), "error without the file name: {e}");
            assert!(!e.message.is_empty());
            return;
        }
    };
    let mesh = &ply.mesh;
    mesh.validate().expect("parse_ply returned an invalid mesh");
    assert!(mesh.positions().iter().flatten().all(|x| x.is_finite()));
    match ply.encoding {
        PlyEncoding::Ascii => assert_eq!(ply.face_lines.len(), mesh.num_faces()),
        _ => assert!(ply.face_lines.is_empty()),
    }
    if mesh.face_offsets().windows(2).any(|w| w[1] - w[0] > 255) {
        return; // PLY's uchar counts, which `write_ply` writes, hold 255 corners.
    }
    let mut bytes = Vec::new();
    write_ply(&mut bytes, mesh.positions(), None, mesh.face_offsets(), mesh.face_verts())
        .expect("write_ply failed on a parsed mesh");
    let back = match parse_ply(&bytes, "written.ply") {
        Ok(b) => b,
        Err(e) => panic!("write_ply output does not read back: {e}"),
    };
    let bits = |p: &[[f64; 3]]| -> Vec<u64> { p.iter().flatten().map(|x| x.to_bits()).collect() };
    assert_eq!(bits(back.mesh.positions()), bits(mesh.positions()));
    assert_eq!(back.mesh.face_offsets(), mesh.face_offsets());
    assert_eq!(back.mesh.face_verts(), mesh.face_verts());
});
