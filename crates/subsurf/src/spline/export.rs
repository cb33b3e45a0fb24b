//! Writers for spline tessellations with colours or a scalar: OBJ with vertex colours
//! (`v x y z r g b`, the extension read by MeshLab and Blender) and binary PLY with colour or
//! scalar properties. The plain writers of [`crate::io`] cover outputs without attributes.

use super::tessellate::SplineTessellation;
use std::io::{self, Write};

/// Colours of [`super::face_colours`] indices, in the spirit of the paper's Fig. 7.
pub const PALETTE: [[u8; 3]; 6] = [
    [230, 159, 0],
    [86, 180, 233],
    [0, 158, 115],
    [240, 228, 66],
    [204, 121, 167],
    [213, 94, 0],
];

/// A tessellation split so that every output quad's base face has its own vertices (copies
/// of the shared ones, bit-identical positions), with each vertex coloured by
/// `colour(base face)`: colours change sharply at patch borders, which per-vertex colours
/// (OBJ) cannot do on shared vertices. Returns positions, normals, colours and CSR faces.
#[allow(clippy::type_complexity)]
pub fn split_by_face(
    t: &SplineTessellation,
    colour: impl Fn(u32) -> [u8; 3],
) -> (
    Vec<[f64; 3]>,
    Vec<[f64; 3]>,
    Vec<[u8; 3]>,
    Vec<u32>,
    Vec<u32>,
) {
    let mut pos = Vec::new();
    let mut nor = Vec::new();
    let mut col = Vec::new();
    let mut offsets = vec![0u32];
    let mut verts = Vec::with_capacity(t.face_verts.len());
    let mut map: Vec<(u32, u32)> = Vec::new(); // (old vertex, new vertex) of the current base face
    let mut current = u32::MAX;
    for q in 0..t.num_faces() {
        let f = t.source[q];
        if f != current {
            current = f;
            map.clear();
        }
        let c = colour(f);
        for &v in &t.face_verts[t.face_offsets[q] as usize..t.face_offsets[q + 1] as usize] {
            let nv = match map.iter().find(|x| x.0 == v) {
                Some(x) => x.1,
                None => {
                    let nv = pos.len() as u32;
                    pos.push(t.positions[v as usize]);
                    nor.push(t.normals[v as usize]);
                    col.push(c);
                    map.push((v, nv));
                    nv
                }
            };
            verts.push(nv);
        }
        offsets.push(verts.len() as u32);
    }
    (pos, nor, col, offsets, verts)
}

/// A blue (0) to red (`max`) colour ramp of `values` (`max` = the largest value, or 1 if
/// none is positive).
pub fn scalar_colours(values: &[f64]) -> Vec<[u8; 3]> {
    let max = values.iter().cloned().fold(0.0f64, f64::max);
    let max = if max > 0.0 { max } else { 1.0 };
    values
        .iter()
        .map(|&x| {
            let t = (x / max).clamp(0.0, 1.0);
            let r = (255.0 * t).round() as u8;
            let g = (255.0 * (1.0 - (2.0 * t - 1.0).abs()) * 0.8).round() as u8;
            let b = (255.0 * (1.0 - t)).round() as u8;
            [r, g, b]
        })
        .collect()
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

fn check(
    n: usize,
    normals: Option<&[[f64; 3]]>,
    colours: Option<&[[u8; 3]]>,
    offsets: &[u32],
    verts: &[u32],
) -> io::Result<()> {
    if normals.is_some_and(|x| x.len() != n) || colours.is_some_and(|x| x.len() != n) {
        return Err(invalid("one normal and colour per vertex needed".into()));
    }
    if offsets.first() != Some(&0) || offsets.last().map(|&x| x as usize) != Some(verts.len()) {
        return Err(invalid("inconsistent face offsets".into()));
    }
    if let Some(v) = verts.iter().find(|&&v| v as usize >= n) {
        return Err(invalid(format!(
            "face vertex {v} out of range ({n} vertices)"
        )));
    }
    Ok(())
}

/// Writes OBJ: a `# comment` header, `v x y z r g b` per vertex (colour components in
/// `[0, 1]` with 4 decimals; positions in shortest round-trip form), `vn` per vertex when
/// `normals` is given, and `f a//a …` (or `f a …`) per face, 1-based.
///
/// # Errors
/// Errors of `w`; `InvalidInput` for inconsistent arrays; `InvalidData` for non-finite
/// values.
pub fn write_obj_coloured<W: Write>(
    w: &mut W,
    positions: &[[f64; 3]],
    normals: Option<&[[f64; 3]]>,
    colours: &[[u8; 3]],
    face_offsets: &[u32],
    face_verts: &[u32],
    comment: &str,
) -> io::Result<()> {
    check(
        positions.len(),
        normals,
        Some(colours),
        face_offsets,
        face_verts,
    )?;
    let mut out = io::BufWriter::new(w);
    writeln!(out, "# written by subsurf {}", env!("CARGO_PKG_VERSION"))?;
    for line in comment.lines() {
        writeln!(out, "# {line}")?;
    }
    for (p, c) in positions.iter().zip(colours) {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("non-finite coordinate ({}, {}, {})", p[0], p[1], p[2]),
            ));
        }
        writeln!(
            out,
            "v {:?} {:?} {:?} {:.4} {:.4} {:.4}",
            p[0],
            p[1],
            p[2],
            c[0] as f64 / 255.0,
            c[1] as f64 / 255.0,
            c[2] as f64 / 255.0
        )?;
    }
    if let Some(ns) = normals {
        for n in ns {
            writeln!(out, "vn {:?} {:?} {:?}", n[0], n[1], n[2])?;
        }
    }
    for f in face_offsets.windows(2) {
        out.write_all(b"f")?;
        for &v in &face_verts[f[0] as usize..f[1] as usize] {
            if normals.is_some() {
                write!(out, " {}//{}", v + 1, v + 1)?;
            } else {
                write!(out, " {}", v + 1)?;
            }
        }
        out.write_all(b"\n")?;
    }
    out.flush()
}

/// What [`write_ply_attributes`] writes besides positions and faces.
#[derive(Clone, Copy, Debug, Default)]
pub struct PlyAttributes<'a> {
    /// Per-vertex normals: `property double nx ny nz`.
    pub normals: Option<&'a [[f64; 3]]>,
    /// Per-vertex colours: `property uchar red green blue`.
    pub vertex_colours: Option<&'a [[u8; 3]]>,
    /// A per-vertex scalar `(name, values)`: `property double NAME`.
    pub vertex_scalar: Option<(&'a str, &'a [f64])>,
    /// Per-face colours: `property uchar red green blue` on the face element.
    pub face_colours: Option<&'a [[u8; 3]]>,
}

/// Writes binary little-endian PLY: vertex element `x y z` (double), then the optional
/// `nx ny nz` (double), `red green blue` (uchar) and scalar (double) properties; face element
/// `vertex_indices` (list uchar int), then the optional face `red green blue` (uchar).
///
/// # Errors
/// Errors of `w`; `InvalidInput` for inconsistent arrays or a face of more than 255 vertices.
pub fn write_ply_attributes<W: Write>(
    w: &mut W,
    positions: &[[f64; 3]],
    face_offsets: &[u32],
    face_verts: &[u32],
    attrs: &PlyAttributes,
) -> io::Result<()> {
    let n = positions.len();
    check(
        n,
        attrs.normals,
        attrs.vertex_colours,
        face_offsets,
        face_verts,
    )?;
    let nf = face_offsets.len() - 1;
    if attrs.vertex_scalar.is_some_and(|s| s.1.len() != n)
        || attrs.face_colours.is_some_and(|c| c.len() != nf)
    {
        return Err(invalid(
            "one scalar per vertex and colour per face needed".into(),
        ));
    }
    let mut out = io::BufWriter::new(w);
    let mut h = String::from("ply\nformat binary_little_endian 1.0\n");
    h.push_str(&format!(
        "comment written by subsurf {}\nelement vertex {n}\n",
        env!("CARGO_PKG_VERSION")
    ));
    h.push_str("property double x\nproperty double y\nproperty double z\n");
    if attrs.normals.is_some() {
        h.push_str("property double nx\nproperty double ny\nproperty double nz\n");
    }
    if attrs.vertex_colours.is_some() {
        h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    if let Some((name, _)) = attrs.vertex_scalar {
        h.push_str(&format!("property double {name}\n"));
    }
    h.push_str(&format!(
        "element face {nf}\nproperty list uchar int vertex_indices\n"
    ));
    if attrs.face_colours.is_some() {
        h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    h.push_str("end_header\n");
    out.write_all(h.as_bytes())?;
    for i in 0..n {
        for x in positions[i] {
            out.write_all(&x.to_le_bytes())?;
        }
        if let Some(ns) = attrs.normals {
            for x in ns[i] {
                out.write_all(&x.to_le_bytes())?;
            }
        }
        if let Some(c) = attrs.vertex_colours {
            out.write_all(&c[i])?;
        }
        if let Some((_, s)) = attrs.vertex_scalar {
            out.write_all(&s[i].to_le_bytes())?;
        }
    }
    for f in 0..nf {
        let fv = &face_verts[face_offsets[f] as usize..face_offsets[f + 1] as usize];
        if fv.len() > 255 {
            return Err(invalid(format!("face {f} has {} vertices", fv.len())));
        }
        out.write_all(&[fv.len() as u8])?;
        for &v in fv {
            out.write_all(&(v as i32).to_le_bytes())?;
        }
        if let Some(c) = attrs.face_colours {
            out.write_all(&c[f])?;
        }
    }
    out.flush()
}
