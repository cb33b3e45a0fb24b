//! [`write_tessellation`]: one writer for every tessellation ([`Tessellation`], whichever
//! surface it samples), in OBJ, binary PLY, binary STL or binary glTF, with optional
//! colours, a per-vertex scalar and the control mesh's edges.

#[cfg(feature = "gltf")]
use super::gltf::{face_edges, write_glb, GlbLines, GlbMesh};
use super::obj::{write_obj, WriteOptions};
use super::ply::write_ply;
use super::stl::write_stl;
use super::Up;
use crate::limit::Tessellation;
use crate::mesh::PolyMesh;
use std::io::{self, Write};

/// The file formats [`write_tessellation`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TessellationFormat {
    /// Wavefront OBJ: positions in shortest round-trip form, `vn` normals, vertex colours
    /// as `v x y z r g b` (the extension MeshLab and Blender read).
    Obj,
    /// Binary little-endian PLY: `double` positions and normals, `uchar` colours.
    Ply,
    /// Binary STL: `float` triangles (quads are split along their `a c` diagonal).
    Stl,
    /// Binary glTF 2.0 (`.glb`): `float` positions and normals, triangles, `+Y` up.
    Glb,
}

impl TessellationFormat {
    /// Every format, in the order of [`extension`](Self::extension)s listed to users.
    pub const ALL: [Self; 4] = [Self::Glb, Self::Obj, Self::Ply, Self::Stl];

    /// The format of a file name extension (any case, without the dot).
    pub fn from_extension(ext: &str) -> Option<Self> {
        match ext.to_ascii_lowercase().as_str() {
            "obj" => Some(Self::Obj),
            "ply" => Some(Self::Ply),
            "stl" => Some(Self::Stl),
            "glb" => Some(Self::Glb),
            _ => None,
        }
    }

    /// The format's file name extension.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Obj => "obj",
            Self::Ply => "ply",
            Self::Stl => "stl",
            Self::Glb => "glb",
        }
    }

    /// Whether the format stores coordinates in single precision (STL and glTF), so that
    /// values beyond about ±3.4e38 cannot be written.
    pub fn single_precision(self) -> bool {
        matches!(self, Self::Stl | Self::Glb)
    }

    /// Whether the format stores triangles only (STL and glTF): a tessellation in quads is
    /// split on writing, so ask [`tessellate`](crate::limit::tessellate) for triangles,
    /// which it splits along the shorter diagonal.
    pub fn triangles_only(self) -> bool {
        matches!(self, Self::Stl | Self::Glb)
    }
}

/// Colours written with a tessellation.
#[derive(Clone, Copy, Debug)]
pub enum Colours<'a> {
    /// One colour per output vertex.
    PerVertex(&'a [[u8; 3]]),
    /// One colour per output face. PLY stores face colours; OBJ and glTF colour vertices,
    /// so there each run of output faces with the same base face and colour gets its own
    /// copies of its vertices (bit-identical positions): colours change sharply at face
    /// borders.
    PerFace(&'a [[u8; 3]]),
}

/// What [`write_tessellation`] writes besides positions, normals and faces.
#[derive(Clone, Copy, Debug, Default)]
pub struct TessellationWriteOptions<'a> {
    /// Header comment (OBJ `#` lines, the STL header; PLY and glTF write none).
    pub comment: &'a str,
    /// Colours (OBJ, PLY, glTF; STL has none).
    pub colours: Option<Colours<'a>>,
    /// A per-vertex scalar `(name, values)`: PLY `property double NAME` (PLY only).
    pub vertex_scalar: Option<(&'a str, &'a [f64])>,
    /// glTF: the control mesh, drawn as lines with the surface.
    pub control: Option<&'a PolyMesh>,
    /// glTF: the up axis of the input, turned to glTF's `+Y` up.
    pub up: Up,
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Writes `t` to `w` in `format`, with what `options` adds.
///
/// # Errors
/// Errors of `w`; `InvalidInput` for an option the format cannot store (colours in STL, a
/// scalar outside PLY, a control mesh outside glTF), for arrays of the wrong length, and for
/// what the format's writer refuses ([`write_obj`], [`write_ply`], [`write_stl`],
/// [`write_glb`]).
pub fn write_tessellation<W: Write>(
    w: &mut W,
    format: TessellationFormat,
    t: &Tessellation,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    check_options(format, t, options)?;
    match (format, options.colours) {
        (TessellationFormat::Obj, None) => {
            let mesh = t.to_polymesh().map_err(|e| invalid(e.to_string()))?;
            let opts = WriteOptions {
                normals: Some(&t.normals),
                scheme: None,
                comment: Some(options.comment),
            };
            write_obj(w, &mesh, &opts)
        }
        (TessellationFormat::Obj, Some(colours)) => {
            let c = Coloured::new(t, colours);
            write_obj_coloured(w, &c, options.comment)
        }
        (TessellationFormat::Ply, None) if options.vertex_scalar.is_none() => write_ply(
            w,
            &t.positions,
            Some(&t.normals),
            &t.face_offsets,
            &t.face_verts,
        ),
        (TessellationFormat::Ply, colours) => write_ply_attributes(w, t, colours, options),
        (TessellationFormat::Stl, _) => write_stl(
            w,
            &t.positions,
            &t.face_offsets,
            &t.face_verts,
            options.comment,
        ),
        #[cfg(feature = "gltf")]
        (TessellationFormat::Glb, colours) => write_glb_tessellation(w, t, colours, options),
        #[cfg(not(feature = "gltf"))]
        (TessellationFormat::Glb, _) => Err(io::Error::new(
            io::ErrorKind::Unsupported,
            "glTF output needs subsurf's `gltf` feature",
        )),
    }
}

fn check_options(
    format: TessellationFormat,
    t: &Tessellation,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    if format == TessellationFormat::Stl && options.colours.is_some() {
        return Err(invalid("STL stores no colours".into()));
    }
    if format != TessellationFormat::Ply && options.vertex_scalar.is_some() {
        return Err(invalid("only PLY stores a per-vertex scalar".into()));
    }
    if format != TessellationFormat::Glb && options.control.is_some() {
        return Err(invalid("only glTF stores the control mesh".into()));
    }
    let (nv, nf) = (t.num_vertices(), t.num_faces());
    let ok = match options.colours {
        Some(Colours::PerVertex(c)) => c.len() == nv,
        Some(Colours::PerFace(c)) => c.len() == nf,
        None => true,
    } && options.vertex_scalar.is_none_or(|(_, s)| s.len() == nv)
        && t.normals.len() == nv
        && t.source.len() == nf;
    if ok {
        Ok(())
    } else {
        Err(invalid(
            "one normal, colour and scalar per vertex (or colour per face) needed".into(),
        ))
    }
}

/// A tessellation with one colour per vertex: `t` itself for per-vertex colours, else
/// copies of the vertices per run of faces with the same base face and colour.
struct Coloured<'a> {
    positions: std::borrow::Cow<'a, [[f64; 3]]>,
    normals: std::borrow::Cow<'a, [[f64; 3]]>,
    colours: std::borrow::Cow<'a, [[u8; 3]]>,
    face_offsets: &'a [u32],
    face_verts: std::borrow::Cow<'a, [u32]>,
}

impl<'a> Coloured<'a> {
    fn new(t: &'a Tessellation, colours: Colours<'a>) -> Self {
        use std::borrow::Cow::{Borrowed, Owned};
        match colours {
            Colours::PerVertex(c) => Self {
                positions: Borrowed(&t.positions),
                normals: Borrowed(&t.normals),
                colours: Borrowed(c),
                face_offsets: &t.face_offsets,
                face_verts: Borrowed(&t.face_verts),
            },
            Colours::PerFace(c) => {
                let (positions, normals, colours, face_verts) = split_by_face(t, c);
                Self {
                    positions: Owned(positions),
                    normals: Owned(normals),
                    colours: Owned(colours),
                    face_offsets: &t.face_offsets,
                    face_verts: Owned(face_verts),
                }
            }
        }
    }
}

/// Per-vertex copies for per-face colours: each run of consecutive output faces with the
/// same base face and colour gets its own copies of the vertices it uses, coloured with its
/// colour. Returns positions, normals, colours and the faces' new vertex indices.
#[allow(clippy::type_complexity)]
fn split_by_face(
    t: &Tessellation,
    face_colours: &[[u8; 3]],
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[u8; 3]>, Vec<u32>) {
    const UNSET: u32 = u32::MAX;
    let mut pos = Vec::new();
    let mut nor = Vec::new();
    let mut col = Vec::new();
    let mut verts = Vec::with_capacity(t.face_verts.len());
    // New index of each old vertex in the current run, and the run's old vertices.
    let mut map = vec![UNSET; t.num_vertices()];
    let mut in_run: Vec<u32> = Vec::new();
    let mut run = None;
    for q in 0..t.num_faces() {
        let key = (t.source[q].0, face_colours[q]);
        if run != Some(key) {
            run = Some(key);
            in_run.drain(..).for_each(|v| map[v as usize] = UNSET);
        }
        for &v in t.face(q) {
            if map[v as usize] == UNSET {
                map[v as usize] = pos.len() as u32;
                in_run.push(v);
                pos.push(t.positions[v as usize]);
                nor.push(t.normals[v as usize]);
                col.push(face_colours[q]);
            }
            verts.push(map[v as usize]);
        }
    }
    (pos, nor, col, verts)
}

fn non_finite(p: &[f64; 3]) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("non-finite coordinate ({}, {}, {})", p[0], p[1], p[2]),
    )
}

/// OBJ with vertex colours: a `#` header, `v x y z r g b` per vertex (colour components in
/// `[0, 1]` with 4 decimals; positions in shortest round-trip form), `vn` per vertex and
/// `f a//a …` per face, 1-based.
fn write_obj_coloured<W: Write>(w: &mut W, c: &Coloured, comment: &str) -> io::Result<()> {
    let mut out = io::BufWriter::new(w);
    writeln!(out, "# written by subsurf {}", env!("CARGO_PKG_VERSION"))?;
    for line in comment.lines() {
        writeln!(out, "# {line}")?;
    }
    for (p, k) in c.positions.iter().zip(c.colours.iter()) {
        if !p.iter().all(|x| x.is_finite()) {
            return Err(non_finite(p));
        }
        let [r, g, b] = k.map(|x| f64::from(x) / 255.0);
        writeln!(
            out,
            "v {:?} {:?} {:?} {r:.4} {g:.4} {b:.4}",
            p[0], p[1], p[2]
        )?;
    }
    for n in c.normals.iter() {
        writeln!(out, "vn {:?} {:?} {:?}", n[0], n[1], n[2])?;
    }
    for f in c.face_offsets.windows(2) {
        out.write_all(b"f")?;
        for &v in &c.face_verts[f[0] as usize..f[1] as usize] {
            write!(out, " {}//{}", v + 1, v + 1)?;
        }
        out.write_all(b"\n")?;
    }
    out.flush()
}

/// Binary little-endian PLY: vertex element `x y z nx ny nz` (double), then the optional
/// `red green blue` (uchar) and scalar (double) properties; face element `vertex_indices`
/// (list uchar int), then the optional face `red green blue` (uchar).
fn write_ply_attributes<W: Write>(
    w: &mut W,
    t: &Tessellation,
    colours: Option<Colours>,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    let (n, nf) = (t.num_vertices(), t.num_faces());
    let (vertex_colours, face_colours) = match colours {
        Some(Colours::PerVertex(c)) => (Some(c), None),
        Some(Colours::PerFace(c)) => (None, Some(c)),
        None => (None, None),
    };
    let mut out = io::BufWriter::new(w);
    let mut h = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by subsurf {}\nelement vertex \
         {n}\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\n\
         property double ny\nproperty double nz\n",
        env!("CARGO_PKG_VERSION")
    );
    const RGB: &str = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if vertex_colours.is_some() {
        h.push_str(RGB);
    }
    if let Some((name, _)) = options.vertex_scalar {
        h.push_str(&format!("property double {name}\n"));
    }
    h.push_str(&format!(
        "element face {nf}\nproperty list uchar int vertex_indices\n"
    ));
    if face_colours.is_some() {
        h.push_str(RGB);
    }
    h.push_str("end_header\n");
    out.write_all(h.as_bytes())?;
    for i in 0..n {
        for x in t.positions[i].iter().chain(&t.normals[i]) {
            out.write_all(&x.to_le_bytes())?;
        }
        if let Some(c) = vertex_colours {
            out.write_all(&c[i])?;
        }
        if let Some((_, s)) = options.vertex_scalar {
            out.write_all(&s[i].to_le_bytes())?;
        }
    }
    for f in 0..nf {
        let fv = t.face(f);
        if fv.len() > 255 {
            return Err(invalid(format!("face {f} has {} vertices", fv.len())));
        }
        out.write_all(&[fv.len() as u8])?;
        for &v in fv {
            out.write_all(&(v as i32).to_le_bytes())?;
        }
        if let Some(c) = face_colours {
            out.write_all(&c[f])?;
        }
    }
    out.flush()
}

#[cfg(feature = "gltf")]
/// glTF: the tessellation (with vertex colours, per-face ones split as in OBJ) and, when
/// given, the control mesh's edges as lines.
fn write_glb_tessellation<W: Write>(
    w: &mut W,
    t: &Tessellation,
    colours: Option<Colours>,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    let c = colours.map(|k| Coloured::new(t, k));
    let rgb: Option<Vec<[f32; 3]>> = c.as_ref().map(|c| {
        c.colours
            .iter()
            .map(|k| k.map(|x| f32::from(x) / 255.0))
            .collect()
    });
    let edges = options
        .control
        .map(|m| face_edges(m.face_offsets(), m.face_verts()));
    let (positions, normals, face_verts): (&[[f64; 3]], &[[f64; 3]], &[u32]) = match &c {
        Some(c) => (&c.positions, &c.normals, &c.face_verts),
        None => (&t.positions, &t.normals, &t.face_verts),
    };
    let glb = GlbMesh {
        name: "limit surface",
        positions,
        normals: Some(normals),
        colors: rgb.as_deref(),
        face_offsets: &t.face_offsets,
        face_verts,
        control: options
            .control
            .zip(edges.as_deref())
            .map(|(m, lines)| GlbLines {
                positions: m.positions(),
                lines,
            }),
        up: options.up,
    };
    write_glb(w, &glb)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads side by side sharing an edge, from base faces 0 and 1.
    fn two_quads() -> Tessellation {
        Tessellation {
            rate: 1,
            positions: vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [2., 0., 0.],
                [0., 1., 0.],
                [1., 1., 0.],
                [2., 1., 0.],
            ],
            normals: vec![[0., 0., 1.]; 6],
            face_offsets: vec![0, 4, 8],
            face_verts: vec![0, 1, 4, 3, 1, 2, 5, 4],
            source: vec![(0, 0), (1, 0)],
            points: Vec::new(),
        }
    }

    #[test]
    fn per_face_colours_copy_shared_vertices() {
        let t = two_quads();
        let (p, n, c, fv) = split_by_face(&t, &[[255, 0, 0], [0, 0, 255]]);
        // The shared edge's two vertices are copied: 8 vertices, one colour each.
        assert_eq!((p.len(), n.len(), c.len()), (8, 8, 8));
        assert_eq!(fv, vec![0, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(p[1], p[4]);
        assert_eq!((c[0], c[7]), ([255, 0, 0], [0, 0, 255]));
        // Same base face and colour: one run, shared vertices kept shared.
        let mut same = t.clone();
        same.source = vec![(0, 0), (0, 0)];
        let (p, ..) = split_by_face(&same, &[[9, 9, 9], [9, 9, 9]]);
        assert_eq!(p.len(), 6);
    }

    #[test]
    fn formats_refuse_what_they_cannot_store() {
        let t = two_quads();
        let red = [[255, 0, 0]; 2];
        let colours = TessellationWriteOptions {
            colours: Some(Colours::PerFace(&red)),
            ..Default::default()
        };
        let write = |f, o: &TessellationWriteOptions| {
            write_tessellation(&mut Vec::new(), f, &t, o).map_err(|e| e.to_string())
        };
        assert!(write(TessellationFormat::Stl, &colours)
            .unwrap_err()
            .contains("STL stores no colours"));
        let scalar = TessellationWriteOptions {
            vertex_scalar: Some(("w", &[0.0; 6])),
            ..Default::default()
        };
        assert!(write(TessellationFormat::Obj, &scalar).is_err());
        assert!(write(TessellationFormat::Ply, &scalar).is_ok());
        let short = TessellationWriteOptions {
            colours: Some(Colours::PerVertex(&red)),
            ..Default::default()
        };
        assert!(write(TessellationFormat::Ply, &short).is_err());
        for f in TessellationFormat::ALL {
            assert!(write(f, &colours).is_ok() || f == TessellationFormat::Stl);
            assert_eq!(TessellationFormat::from_extension(f.extension()), Some(f));
        }
    }

    #[test]
    fn coloured_obj_has_colours_normals_and_faces() {
        let t = two_quads();
        let mut out = Vec::new();
        let opts = TessellationWriteOptions {
            comment: "test",
            colours: Some(Colours::PerFace(&[[255, 0, 0], [0, 0, 255]])),
            ..Default::default()
        };
        write_tessellation(&mut out, TessellationFormat::Obj, &t, &opts).unwrap();
        let s = String::from_utf8(out).unwrap();
        assert!(s.contains("# test\n"));
        assert!(s.contains("v 1.0 0.0 0.0 1.0000 0.0000 0.0000\n"));
        assert!(s.contains("v 1.0 0.0 0.0 0.0000 0.0000 1.0000\n"));
        assert_eq!(s.matches("\nvn ").count(), 8);
        assert!(s.contains("f 5//5 6//6 7//7 8//8\n"));
    }
}
