//! PLY (Stanford polygon file format): a reader of ASCII and binary files, a binary
//! little-endian writer.
//!
//! [`parse_ply`] reads a polygon mesh from any PLY file (ASCII, binary little- or
//! big-endian; see its docs and [`PlyFile`]); it is what the command line reads `.ply`
//! input with, and any file that starts with the line `ply`.
//!
//! [`write_ply`] writes exactly this layout:
//!
//! ```text
//! ply
//! format binary_little_endian 1.0
//! comment written by subsurf VERSION
//! element vertex V
//! property double x
//! property double y
//! property double z
//! property double nx          (these three only with normals)
//! property double ny
//! property double nz
//! element face F
//! property list uchar int vertex_indices
//! end_header
//! ```
//!
//! (each header line ends with `\n`), then `V` vertex records of 3 (or 6) little-endian
//! `f64`, then `F` face records: a `u8` vertex count and that many little-endian `i32`
//! indices (0-based). The file is `header + V · 24 (48 with normals) + Σ (1 + 4 · size)`
//! bytes. Coordinates are stored as `f64`, so nothing is lost.
//!
//! [`read_ply`] reads such files back with their normals.

mod read;

pub(crate) use read::{header_complete, parse_ply_within, PlyRefusal};
pub use read::{parse_ply, PlyEncoding, PlyError, PlyFile, MAX_HEADER};

use std::io::{self, Write};

/// Writes a polygon mesh as binary little-endian PLY (see the module docs).
///
/// Faces are in CSR form: face `f` has the vertices
/// `face_verts[face_offsets[f] .. face_offsets[f + 1]]`.
///
/// # Errors
/// Errors of `w`; [`io::ErrorKind::InvalidInput`] when the CSR arrays are inconsistent, an
/// index is out of range or above `i32::MAX`, a face has fewer than 3 or more than 255
/// vertices, or `normals` does not have one normal per vertex;
/// [`io::ErrorKind::InvalidData`] for a non-finite coordinate or normal.
pub fn write_ply<W: Write>(
    w: &mut W,
    positions: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    face_offsets: &[u32],
    face_verts: &[u32],
) -> io::Result<()> {
    check_faces(positions.len(), face_offsets, face_verts, 255)?;
    if positions.len() > i32::MAX as usize + 1 {
        return Err(invalid_input(format!(
            "{} vertices: PLY's int indices reach only {}",
            positions.len(),
            i32::MAX
        )));
    }
    check_finite(positions, "vertex", "coordinate")?;
    if let Some(n) = normals {
        if n.len() != positions.len() {
            return Err(invalid_input(format!(
                "{} normals given for {} vertices; PLY output needs one per vertex",
                n.len(),
                positions.len()
            )));
        }
        check_finite(n, "the normal of vertex", "value")?;
    }
    let num_faces = face_offsets.len().saturating_sub(1);
    let mut header = String::new();
    header.push_str("ply\nformat binary_little_endian 1.0\n");
    header.push_str(&format!(
        "comment written by subsurf {}\n",
        env!("CARGO_PKG_VERSION")
    ));
    header.push_str(&format!("element vertex {}\n", positions.len()));
    for c in ["x", "y", "z"] {
        header.push_str(&format!("property double {c}\n"));
    }
    if normals.is_some() {
        for c in ["nx", "ny", "nz"] {
            header.push_str(&format!("property double {c}\n"));
        }
    }
    header.push_str(&format!("element face {num_faces}\n"));
    header.push_str("property list uchar int vertex_indices\nend_header\n");

    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK + 2048);
    buf.extend_from_slice(header.as_bytes());
    for (i, p) in positions.iter().enumerate() {
        p.iter()
            .for_each(|x| buf.extend_from_slice(&x.to_le_bytes()));
        if let Some(n) = normals {
            n[i].iter()
                .for_each(|x| buf.extend_from_slice(&x.to_le_bytes()));
        }
        flush(&mut buf, w, false)?;
    }
    for f in 0..num_faces {
        let fv = &face_verts[face_offsets[f] as usize..face_offsets[f + 1] as usize];
        buf.push(fv.len() as u8);
        fv.iter()
            .for_each(|&v| buf.extend_from_slice(&(v as i32).to_le_bytes()));
        flush(&mut buf, w, false)?;
    }
    flush(&mut buf, w, true)
}

/// A mesh read by [`read_ply`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// Vertex positions (`x y z`).
    pub positions: Vec<[f64; 3]>,
    /// Vertex normals (`nx ny nz`), when the file has all three.
    pub normals: Option<Vec<[f64; 3]>>,
    /// CSR face offsets.
    pub face_offsets: Vec<u32>,
    /// CSR face-vertex indices.
    pub face_verts: Vec<u32>,
}

/// Reads a PLY file as [`parse_ply`] does, with the vertices' normals (`nx ny nz`, when
/// the file has all three) and without building a [`PolyMesh`](crate::mesh::PolyMesh):
/// for reading back what [`write_ply`] wrote.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] with the message of [`parse_ply`]'s error.
pub fn read_ply(bytes: &[u8]) -> io::Result<PlyMesh> {
    let data = read::read_data(bytes, "PLY", None).map_err(|e| match e {
        PlyRefusal::Ply(e) => invalid_data(e.to_string()),
        PlyRefusal::TooLarge { .. } => unreachable!("no memory limit was given"),
    })?;
    Ok(PlyMesh {
        positions: data.positions,
        normals: data.normals,
        face_offsets: data.face_offsets,
        face_verts: data.face_verts,
    })
}

/// Bytes gathered before handing them to the writer.
const CHUNK: usize = 1 << 16;

fn flush<W: Write>(buf: &mut Vec<u8>, w: &mut W, force: bool) -> io::Result<()> {
    if force || buf.len() >= CHUNK {
        w.write_all(buf)?;
        buf.clear();
    }
    Ok(())
}

fn invalid_input(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

fn invalid_data(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

/// Checks CSR faces: offsets from 0, non-decreasing, ending at `face_verts.len()`; every
/// face of 3 to `max_size` vertices, all below `num_vertices`.
pub(crate) fn check_faces(
    num_vertices: usize,
    face_offsets: &[u32],
    face_verts: &[u32],
    max_size: usize,
) -> io::Result<()> {
    if face_offsets.first().is_some_and(|&o| o != 0)
        || face_offsets.last().map_or(0, |&o| o as usize) != face_verts.len()
    {
        return Err(invalid_input(
            "face offsets must start at 0 and end at the number of face-vertices".into(),
        ));
    }
    for (f, w) in face_offsets.windows(2).enumerate() {
        if w[1] < w[0] {
            return Err(invalid_input(format!("offset of face {f} decreases")));
        }
        let size = (w[1] - w[0]) as usize;
        if size < 3 {
            return Err(invalid_input(format!(
                "face {f} has {size} vertices; a face needs at least 3"
            )));
        }
        if size > max_size {
            return Err(invalid_input(format!(
                "face {f} has {size} vertices; at most {max_size} can be written"
            )));
        }
        if let Some(&v) = face_verts[w[0] as usize..w[1] as usize]
            .iter()
            .find(|&&v| v as usize >= num_vertices)
        {
            return Err(invalid_input(format!(
                "face {f} refers to vertex {v} of {num_vertices}"
            )));
        }
    }
    Ok(())
}

fn check_finite(values: &[[f64; 3]], what: &str, kind: &str) -> io::Result<()> {
    match values.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(i) => {
            let p = values[i];
            Err(invalid_data(format!(
                "{what} {i} has a non-finite {kind} ({}, {}, {})",
                p[0], p[1], p[2]
            )))
        }
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_with_and_without_normals() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.1],
            [0.0, 1.0, -0.0],
        ];
        let n = [[0.0, 0.0, 1.0]; 4];
        let (offs, verts) = (vec![0, 3, 7], vec![0, 1, 2, 0, 1, 2, 3]);
        for normals in [None, Some(&n[..])] {
            let mut out = Vec::new();
            write_ply(&mut out, &p, normals, &offs, &verts).unwrap();
            let end = out.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
            let per_vertex = if normals.is_some() { 48 } else { 24 };
            assert_eq!(out.len(), end + 4 * per_vertex + (1 + 12) + (1 + 16));
            let back = read_ply(&out).unwrap();
            assert_eq!(back.positions, p);
            assert_eq!(back.normals.as_deref(), normals);
            assert_eq!(
                (back.face_offsets, back.face_verts),
                (offs.clone(), verts.clone())
            );
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let p = vec![[0.0; 3]; 3];
        let mut out = Vec::new();
        let big: Vec<u32> = (0..256).map(|i| i % 3).collect();
        let e = write_ply(&mut out, &p, None, &[0, 256], &big).unwrap_err();
        assert!(e.to_string().contains("256 vertices"), "{e}");
        let e = write_ply(&mut out, &p, None, &[0, 3], &[0, 1, 3]).unwrap_err();
        assert!(e.to_string().contains("vertex 3"), "{e}");
        let e = write_ply(&mut out, &[[f64::NAN; 3]; 3], None, &[0, 3], &[0, 1, 2]).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::InvalidData);
        assert!(read_ply(b"ply\nformat ascii 1.0\nend_header\n").is_err());
        assert!(read_ply(b"solid x").is_err());
        write_ply(&mut out, &p, None, &[0, 3], &[0, 1, 2]).unwrap();
        assert!(read_ply(&out[..out.len() - 1]).is_err());
    }
}
