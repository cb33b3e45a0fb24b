//! Binary STL, written by hand.
//!
//! Layout (all little-endian): an 80-byte header, a `u32` triangle count, then per
//! triangle 50 bytes: its unit normal (3 × `f32`), its three vertices (9 × `f32`) and a
//! `u16` attribute count (0). A file of `T` triangles is `84 + 50 · T` bytes.
//!
//! STL stores **`f32`**: coordinates are rounded to single precision (about 7 significant
//! digits), so an STL file is a lossy copy of the `f64` surface; use OBJ or PLY to keep
//! full precision. STL has no shared vertices and no per-vertex normals either; the
//! normal of each triangle is computed from its (`f64`) geometry.

use crate::geom;
use std::io::{self, Write};

use super::ply::check_faces;

/// Writes a polygon mesh as binary STL (see the module docs).
///
/// Faces are in CSR form (face `f` has the vertices
/// `face_verts[face_offsets[f] .. face_offsets[f + 1]]`); a face with more than three
/// vertices is fan-triangulated from its first vertex (`v0 v1 v2`, `v0 v2 v3`, ...), which
/// is right for convex faces. The header holds `name` (truncated to 80 bytes, padded with
/// spaces; a name that begins with `solid`, which readers would take for ASCII STL, is
/// written as `binary STL: name`). Each triangle's normal is `(b − a) × (c − a)`,
/// normalised, or zero for a degenerate triangle.
///
/// # Errors
/// Errors of `w`; [`io::ErrorKind::InvalidInput`] when the CSR arrays are inconsistent, an
/// index is out of range, a face has fewer than 3 vertices or there are more than
/// `u32::MAX` triangles; [`io::ErrorKind::InvalidData`] when a coordinate is not finite
/// or outside the range of `f32`.
pub fn write_stl<W: Write>(
    w: &mut W,
    positions: &[[f64; 3]],
    face_offsets: &[u32],
    face_verts: &[u32],
    name: &str,
) -> io::Result<()> {
    check_faces(positions.len(), face_offsets, face_verts, usize::MAX)?;
    let single: Vec<[f32; 3]> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let q = p.map(|x| x as f32);
            if q.iter().all(|x| x.is_finite()) {
                Ok(q)
            } else {
                Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "vertex {i} ({}, {}, {}) cannot be stored as f32",
                        p[0], p[1], p[2]
                    ),
                ))
            }
        })
        .collect::<io::Result<_>>()?;
    let triangles: u64 = face_offsets
        .windows(2)
        .map(|w| u64::from(w[1] - w[0]) - 2)
        .sum();
    let count = u32::try_from(triangles).map_err(|_| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{triangles} triangles: binary STL can hold at most {}",
                u32::MAX
            ),
        )
    })?;

    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK + 256);
    buf.extend_from_slice(&header(name));
    buf.extend_from_slice(&count.to_le_bytes());
    for f in face_offsets.windows(2) {
        let fv = &face_verts[f[0] as usize..f[1] as usize];
        for k in 1..fv.len() - 1 {
            let tri = [fv[0], fv[k], fv[k + 1]].map(|v| v as usize);
            let n = normal(&positions[tri[0]], &positions[tri[1]], &positions[tri[2]]);
            for x in n {
                buf.extend_from_slice(&(x as f32).to_le_bytes());
            }
            for v in tri {
                for x in single[v] {
                    buf.extend_from_slice(&x.to_le_bytes());
                }
            }
            buf.extend_from_slice(&0u16.to_le_bytes());
            if buf.len() >= CHUNK {
                w.write_all(&buf)?;
                buf.clear();
            }
        }
    }
    w.write_all(&buf)
}

/// Bytes gathered before handing them to the writer.
const CHUNK: usize = 1 << 16;

/// The 80-byte header for `name`.
fn header(name: &str) -> [u8; 80] {
    let text = if name.trim_start().starts_with("solid") {
        format!("binary STL: {name}")
    } else {
        name.to_owned()
    };
    let mut h = [b' '; 80];
    let bytes = text.as_bytes();
    let n = bytes.len().min(80);
    h[..n].copy_from_slice(&bytes[..n]);
    h
}

/// The unit normal of triangle `a b c` (counter-clockwise), or zero.
fn normal(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> [f64; 3] {
    geom::normalize_or_zero(geom::cross(&geom::sub(b, a), &geom::sub(c, a)))
}

/// One triangle of a binary STL file.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StlTriangle {
    /// The stored normal.
    pub normal: [f32; 3],
    /// The three vertices.
    pub vertices: [[f32; 3]; 3],
}

/// Reads a binary STL file: its 80-byte header and its triangles.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] when the file is shorter than 84 bytes or its length is
/// not `84 + 50 · count`.
pub fn read_stl(bytes: &[u8]) -> io::Result<([u8; 80], Vec<StlTriangle>)> {
    let bad = |m: String| io::Error::new(io::ErrorKind::InvalidData, m);
    if bytes.len() < 84 {
        return Err(bad(format!(
            "binary STL needs at least 84 bytes, got {}",
            bytes.len()
        )));
    }
    let mut header = [0u8; 80];
    header.copy_from_slice(&bytes[..80]);
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    let expect = 84 + 50 * count;
    if bytes.len() as u64 != expect {
        return Err(bad(format!(
            "binary STL with {count} triangles must be {expect} bytes, got {}",
            bytes.len()
        )));
    }
    let f =
        |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let v = |at: usize| [f(at), f(at + 4), f(at + 8)];
    let triangles = (0..count as usize)
        .map(|t| {
            let at = 84 + 50 * t;
            StlTriangle {
                normal: v(at),
                vertices: [v(at + 12), v(at + 24), v(at + 36)],
            }
        })
        .collect();
    Ok((header, triangles))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fan_triangulates_and_round_trips() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0 / 3.0],
        ];
        let mut out = Vec::new();
        write_stl(&mut out, &p, &[0, 4, 7], &[0, 1, 2, 3, 0, 1, 4], "quad").unwrap();
        assert_eq!(out.len(), 84 + 50 * 3);
        let (h, t) = read_stl(&out).unwrap();
        assert!(h.starts_with(b"quad    "));
        assert_eq!(t.len(), 3);
        assert_eq!(
            t[0].vertices,
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]
        );
        assert_eq!(t[1].vertices[2], [0.0, 1.0, 0.0]);
        assert_eq!(t[0].normal, [0.0, 0.0, 1.0]);
        // f32: lossy.
        assert_eq!(t[2].vertices[2][2], (1.0f64 / 3.0) as f32);
        let n = t[2].normal;
        assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn solid_names_and_bad_input() {
        assert!(header("solid thing").starts_with(b"binary STL: solid thing"));
        assert_eq!(header(&"x".repeat(100)), [b'x'; 80]);
        let mut out = Vec::new();
        let p = vec![[0.0; 3], [1e300, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let e = write_stl(&mut out, &p, &[0, 3], &[0, 1, 2], "").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidData);
        let e = write_stl(&mut out, &p, &[0, 2], &[0, 1], "").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
        assert!(read_stl(&[0u8; 83]).is_err());
        assert!(read_stl(&[0u8; 85]).is_err());
    }
}
