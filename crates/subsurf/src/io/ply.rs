//! Binary PLY (Stanford polygon file format), little-endian, written by hand.
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
//! [`read_ply`] reads such files back (and, more generally, binary little-endian PLY with
//! `float`/`double` vertex coordinates and a face list of any integer types; other
//! properties and elements are skipped).

use std::io::{self, Write};

/// Writes a polygon mesh as binary little-endian PLY (see the [module docs](self)).
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

/// Scalar types of PLY.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// Reads one value at `at` (little-endian; `b` holds at least `size()` bytes there).
    fn read(self, b: &[u8], at: usize) -> f64 {
        let mut x = [0u8; 8];
        x[..self.size()].copy_from_slice(&b[at..at + self.size()]);
        let x4 = [x[0], x[1], x[2], x[3]];
        match self {
            Self::I8 => f64::from(x[0] as i8),
            Self::U8 => f64::from(x[0]),
            Self::I16 => f64::from(i16::from_le_bytes([x[0], x[1]])),
            Self::U16 => f64::from(u16::from_le_bytes([x[0], x[1]])),
            Self::I32 => f64::from(i32::from_le_bytes(x4)),
            Self::U32 => f64::from(u32::from_le_bytes(x4)),
            Self::F32 => f64::from(f32::from_le_bytes(x4)),
            Self::F64 => f64::from_le_bytes(x),
        }
    }
}

/// A property: a scalar, or a list with a count type and an item type.
#[derive(Clone, Debug)]
struct Property {
    name: String,
    ty: Scalar,
    list: Option<Scalar>,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

/// Reads binary little-endian PLY (see the [module docs](self)): the `vertex` element's
/// `x y z` (and `nx ny nz` when all three are present) and the `face` element's
/// `vertex_indices` (or `vertex_index`) list.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] naming the problem: not PLY, another format than
/// `binary_little_endian 1.0`, a malformed header, missing coordinates, a truncated body,
/// trailing bytes, an out-of-range or negative index.
pub fn read_ply(bytes: &[u8]) -> io::Result<PlyMesh> {
    let end = find_header_end(bytes)?;
    let header = std::str::from_utf8(&bytes[..end])
        .map_err(|_| invalid_data("PLY header is not UTF-8".into()))?;
    let elements = parse_header(header)?;
    let mut at = end;
    let mut mesh = PlyMesh {
        face_offsets: vec![0],
        ..PlyMesh::default()
    };
    let truncated = || invalid_data("PLY body is truncated".into());
    for el in &elements {
        let find = |n: &str| {
            el.props
                .iter()
                .position(|p| p.name == n && p.list.is_none())
        };
        let (xyz, nxyz) = if el.name == "vertex" {
            let xyz = [find("x"), find("y"), find("z")];
            if xyz.iter().any(Option::is_none) {
                return Err(invalid_data("PLY vertex element lacks x, y or z".into()));
            }
            let n = [find("nx"), find("ny"), find("nz")];
            let nxyz = n.iter().all(Option::is_some).then_some(n);
            (Some(xyz), nxyz)
        } else {
            (None, None)
        };
        let face_list = (el.name == "face").then(|| {
            el.props
                .iter()
                .position(|p| {
                    p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index")
                })
                .ok_or_else(|| invalid_data("PLY face element lacks vertex_indices".into()))
        });
        let face_list = face_list.transpose()?;
        if nxyz.is_some() {
            mesh.normals = Some(Vec::with_capacity(el.count));
        }
        let mut values = vec![0.0; el.props.len()];
        for _ in 0..el.count {
            for (k, p) in el.props.iter().enumerate() {
                match p.list {
                    None => {
                        if at + p.ty.size() > bytes.len() {
                            return Err(truncated());
                        }
                        values[k] = p.ty.read(bytes, at);
                        at += p.ty.size();
                    }
                    Some(count_ty) => {
                        if at + count_ty.size() > bytes.len() {
                            return Err(truncated());
                        }
                        let n = count_ty.read(bytes, at);
                        at += count_ty.size();
                        if !(0.0..=f64::from(u32::MAX)).contains(&n) {
                            return Err(invalid_data(format!("PLY list length {n}")));
                        }
                        let n = n as usize;
                        let len = n.checked_mul(p.ty.size()).ok_or_else(truncated)?;
                        if at + len > bytes.len() {
                            return Err(truncated());
                        }
                        if Some(k) == face_list {
                            for i in 0..n {
                                let v = p.ty.read(bytes, at + i * p.ty.size());
                                if !(0.0..f64::from(u32::MAX)).contains(&v) {
                                    return Err(invalid_data(format!("PLY vertex index {v}")));
                                }
                                mesh.face_verts.push(v as u32);
                            }
                            let total = u32::try_from(mesh.face_verts.len())
                                .map_err(|_| invalid_data("too many face vertices".into()))?;
                            mesh.face_offsets.push(total);
                        }
                        at += len;
                    }
                }
            }
            if let Some([x, y, z]) = xyz {
                let g = |i: Option<usize>| values[i.unwrap_or(0)];
                mesh.positions.push([g(x), g(y), g(z)]);
                if let (Some([a, b, c]), Some(n)) = (nxyz, mesh.normals.as_mut()) {
                    n.push([g(a), g(b), g(c)]);
                }
            }
        }
    }
    if at != bytes.len() {
        return Err(invalid_data(format!(
            "PLY has {} bytes after its last element",
            bytes.len() - at
        )));
    }
    if let Some(&v) = mesh
        .face_verts
        .iter()
        .find(|&&v| v as usize >= mesh.positions.len())
    {
        return Err(invalid_data(format!(
            "PLY face refers to vertex {v} of {}",
            mesh.positions.len()
        )));
    }
    Ok(mesh)
}

/// The byte just after `end_header\n`.
fn find_header_end(bytes: &[u8]) -> io::Result<usize> {
    if !bytes.starts_with(b"ply\n") && !bytes.starts_with(b"ply\r\n") {
        return Err(invalid_data("not a PLY file (no 'ply' magic line)".into()));
    }
    let key = b"end_header";
    let mut i = 0;
    while i + key.len() <= bytes.len() {
        if &bytes[i..i + key.len()] == key && (i == 0 || bytes[i - 1] == b'\n') {
            let mut j = i + key.len();
            if bytes.get(j) == Some(&b'\r') {
                j += 1;
            }
            if bytes.get(j) == Some(&b'\n') {
                return Ok(j + 1);
            }
        }
        i += 1;
    }
    Err(invalid_data("PLY header has no end_header line".into()))
}

fn parse_header(header: &str) -> io::Result<Vec<Element>> {
    let mut elements: Vec<Element> = Vec::new();
    let mut format_ok = false;
    for (n, line) in header.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let bad = || invalid_data(format!("PLY header line {}: '{line}'", n + 1));
        match words.first().copied() {
            None | Some("ply") | Some("comment") | Some("obj_info") | Some("end_header") => {}
            Some("format") => {
                if words.get(1..) != Some(&["binary_little_endian", "1.0"][..]) {
                    return Err(invalid_data(format!(
                        "PLY format '{}' is not supported (only binary_little_endian 1.0)",
                        words[1..].join(" ")
                    )));
                }
                format_ok = true;
            }
            Some("element") => {
                let [_, name, count] = words[..] else {
                    return Err(bad());
                };
                let count = count.parse().map_err(|_| bad())?;
                elements.push(Element {
                    name: name.to_owned(),
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let el = elements.last_mut().ok_or_else(bad)?;
                let prop = match words[..] {
                    [_, "list", count, item, name] => Property {
                        name: name.to_owned(),
                        ty: Scalar::parse(item).ok_or_else(bad)?,
                        list: Some(Scalar::parse(count).ok_or_else(bad)?),
                    },
                    [_, ty, name] => Property {
                        name: name.to_owned(),
                        ty: Scalar::parse(ty).ok_or_else(bad)?,
                        list: None,
                    },
                    _ => return Err(bad()),
                };
                el.props.push(prop);
            }
            Some(_) => return Err(bad()),
        }
    }
    if !format_ok {
        return Err(invalid_data("PLY header has no format line".into()));
    }
    Ok(elements)
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
            let end = find_header_end(&out).unwrap();
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
