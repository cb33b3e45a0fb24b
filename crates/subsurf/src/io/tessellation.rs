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
use crate::mesh::{FaceVarying, PolyMesh};
use std::borrow::Cow;
use std::collections::HashMap;
use std::io::{self, Write};

/// The file formats [`write_tessellation`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TessellationFormat {
    /// Wavefront OBJ: positions in shortest round-trip form, `vn` normals, `vt` texture
    /// coordinates with `f v/vt/vn` faces, vertex colours as `v x y z r g b` (the extension
    /// MeshLab and Blender read).
    Obj,
    /// Binary little-endian PLY: `double` positions, normals and texture coordinates
    /// (`s t`), `uchar` colours.
    Ply,
    /// Binary STL: `float` triangles (quads are split along their `a c` diagonal); no
    /// colours, no texture coordinates.
    Stl,
    /// Binary glTF 2.0 (`.glb`): `float` positions, normals and texture coordinates
    /// (`TEXCOORD_0`), triangles, `+Y` up.
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

/// Writes `t` to `w` in `format`, with what `options` adds, and the texture coordinates of
/// `t`'s face-varying channel named `"uv"` (from
/// [`Tessellation::evaluate_face_varying`]) in every format but STL, which cannot store
/// them: OBJ keeps their own indices (`f v/vt/vn`); PLY and glTF store one per vertex, so a
/// vertex on a seam is written once per texture coordinate it takes there.
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
    let uv = t.face_varying.iter().find(|c| c.name() == "uv");
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
            // Texture coordinates keep their own indices: split for the colours only.
            let c = PerVertex::new(t, Some(colours), None);
            write_obj_coloured(w, &c, uv, options.comment)
        }
        (TessellationFormat::Ply, None) if options.vertex_scalar.is_none() && uv.is_none() => {
            write_ply(
                w,
                &t.positions,
                Some(&t.normals),
                &t.face_offsets,
                &t.face_verts,
            )
        }
        (TessellationFormat::Ply, colours) => write_ply_attributes(w, t, colours, uv, options),
        (TessellationFormat::Stl, _) => write_stl(
            w,
            &t.positions,
            &t.face_offsets,
            &t.face_verts,
            options.comment,
        ),
        #[cfg(feature = "gltf")]
        (TessellationFormat::Glb, colours) => write_glb_tessellation(w, t, colours, uv, options),
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

/// A tessellation with one colour and one texture coordinate per written vertex: `t`'s
/// vertices themselves when each has one (per-vertex colours, no texture coordinates),
/// else copies of a vertex per run of faces with the same base face and colour (per-face
/// colours) and per texture coordinate it takes (on a seam). Positions and normals of the
/// copies are bit-identical.
struct PerVertex<'a> {
    t: &'a Tessellation,
    /// Per written vertex, the tessellation's vertex (`None`: the same).
    old: Option<Vec<u32>>,
    face_verts: Cow<'a, [u32]>,
    colours: Option<Cow<'a, [[u8; 3]]>>,
    /// Per written vertex, the first two components of its texture coordinate (OBJ's
    /// convention: origin at the image's bottom-left).
    uvs: Option<Vec<[f64; 2]>>,
}

impl<'a> PerVertex<'a> {
    /// Splits `t`'s vertices for `colours` and `uv` (see the type's docs).
    fn new(t: &'a Tessellation, colours: Option<Colours<'a>>, uv: Option<&FaceVarying>) -> Self {
        let face_colours = match colours {
            Some(Colours::PerFace(c)) => Some(c),
            _ => None,
        };
        let vertex_colours = match colours {
            Some(Colours::PerVertex(c)) => Some(c),
            _ => None,
        };
        if face_colours.is_none() && uv.is_none() {
            return Self {
                t,
                old: None,
                face_verts: Cow::Borrowed(&t.face_verts),
                colours: vertex_colours.map(Cow::Borrowed),
                uvs: None,
            };
        }
        const UNSET: u32 = u32::MAX;
        // Per old vertex, its first copy in the current run and that copy's texture
        // coordinate; further copies (seams) by (vertex, texture coordinate).
        let mut first = vec![UNSET; t.num_vertices()];
        let mut first_uv = vec![UNSET; t.num_vertices()];
        let mut more: HashMap<(u32, u32), u32> = HashMap::new();
        let mut in_run: Vec<u32> = Vec::new();
        let mut run = None;
        let mut old = Vec::new();
        let mut colours_out = Vec::new();
        let mut uvs = Vec::new();
        let mut face_verts = Vec::with_capacity(t.face_verts.len());
        for q in 0..t.num_faces() {
            if let Some(c) = face_colours {
                let key = (t.source[q].0, c[q]);
                if run != Some(key) {
                    run = Some(key);
                    in_run.drain(..).for_each(|v| first[v as usize] = UNSET);
                    more.clear();
                }
            }
            let start = t.face_offsets[q] as usize;
            for (i, &v) in t.face(q).iter().enumerate() {
                let k = uv.map_or(0, |c| c.indices()[start + i]);
                let mut add = || {
                    old.push(v);
                    if let Some(c) = face_colours {
                        colours_out.push(c[q]);
                    } else if let Some(c) = vertex_colours {
                        colours_out.push(c[v as usize]);
                    }
                    if let Some(c) = uv {
                        let x = c.value(k as usize);
                        uvs.push([x[0], x.get(1).copied().unwrap_or(0.0)]);
                    }
                    (old.len() - 1) as u32
                };
                let new = if first[v as usize] == UNSET {
                    first[v as usize] = add();
                    first_uv[v as usize] = k;
                    if face_colours.is_some() {
                        in_run.push(v);
                    }
                    first[v as usize]
                } else if first_uv[v as usize] == k {
                    first[v as usize]
                } else {
                    *more.entry((v, k)).or_insert_with(add)
                };
                face_verts.push(new);
            }
        }
        Self {
            t,
            old: Some(old),
            face_verts: Cow::Owned(face_verts),
            colours: colours.map(|_| Cow::Owned(colours_out)),
            uvs: uv.map(|_| uvs),
        }
    }

    /// `data` (one item per vertex of the tessellation) per written vertex.
    #[cfg(feature = "gltf")]
    fn gather<T: Copy>(&self, data: &'a [T]) -> Cow<'a, [T]> {
        match &self.old {
            None => Cow::Borrowed(data),
            Some(old) => Cow::Owned(old.iter().map(|&v| data[v as usize]).collect()),
        }
    }

    fn num_vertices(&self) -> usize {
        self.old.as_ref().map_or(self.t.num_vertices(), Vec::len)
    }

    /// The tessellation's vertex of written vertex `i`.
    fn vertex(&self, i: usize) -> usize {
        self.old.as_ref().map_or(i, |old| old[i] as usize)
    }
}

fn non_finite(p: &[f64; 3]) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("non-finite coordinate ({}, {}, {})", p[0], p[1], p[2]),
    )
}

/// OBJ with vertex colours: a `#` header, `v x y z r g b` per vertex (colour components in
/// `[0, 1]` with 4 decimals; positions in shortest round-trip form), `vn` per vertex, `vt`
/// per value of `uv`, and `f a//a …` (`f a/t/a …` with `uv`) per face, 1-based.
fn write_obj_coloured<W: Write>(
    w: &mut W,
    c: &PerVertex,
    uv: Option<&FaceVarying>,
    comment: &str,
) -> io::Result<()> {
    let mut out = io::BufWriter::new(w);
    writeln!(out, "# written by subsurf {}", env!("CARGO_PKG_VERSION"))?;
    for line in comment.lines() {
        writeln!(out, "# {line}")?;
    }
    let colours = c.colours.as_deref().unwrap_or_default();
    for (i, k) in colours.iter().enumerate() {
        let p = &c.t.positions[c.vertex(i)];
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
    for i in 0..c.num_vertices() {
        let n = &c.t.normals[c.vertex(i)];
        writeln!(out, "vn {:?} {:?} {:?}", n[0], n[1], n[2])?;
    }
    if let Some(uv) = uv {
        for x in uv.values().chunks_exact(uv.dim()) {
            out.write_all(b"vt")?;
            for x in x {
                write!(out, " {x:?}")?;
            }
            out.write_all(b"\n")?;
        }
    }
    for f in c.t.face_offsets.windows(2) {
        out.write_all(b"f")?;
        for k in f[0] as usize..f[1] as usize {
            let v = c.face_verts[k] + 1;
            match uv {
                Some(uv) => write!(out, " {v}/{}/{v}", uv.indices()[k] + 1)?,
                None => write!(out, " {v}//{v}")?,
            }
        }
        out.write_all(b"\n")?;
    }
    out.flush()
}

/// Binary little-endian PLY: vertex element `x y z nx ny nz` (double), then the optional
/// `red green blue` (uchar), `s t` (double: texture coordinates, each vertex copied per
/// coordinate it takes on a seam) and scalar (double) properties; face element
/// `vertex_indices` (list uchar int), then the optional face `red green blue` (uchar).
fn write_ply_attributes<W: Write>(
    w: &mut W,
    t: &Tessellation,
    colours: Option<Colours>,
    uv: Option<&FaceVarying>,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    let (vertex_colours, face_colours) = match colours {
        Some(Colours::PerVertex(c)) => (Some(Colours::PerVertex(c)), None),
        Some(Colours::PerFace(c)) => (None, Some(c)),
        None => (None, None),
    };
    // PLY stores face colours: split vertices for texture coordinates only.
    let pv = PerVertex::new(t, vertex_colours, uv);
    let (n, nf) = (pv.num_vertices(), t.num_faces());
    let mut out = io::BufWriter::new(w);
    let mut h = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by subsurf {}\nelement vertex \
         {n}\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\n\
         property double ny\nproperty double nz\n",
        env!("CARGO_PKG_VERSION")
    );
    const RGB: &str = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if pv.colours.is_some() {
        h.push_str(RGB);
    }
    if pv.uvs.is_some() {
        h.push_str("property double s\nproperty double t\n");
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
        let v = pv.vertex(i);
        for x in t.positions[v].iter().chain(&t.normals[v]) {
            out.write_all(&x.to_le_bytes())?;
        }
        if let Some(c) = &pv.colours {
            out.write_all(&c[i])?;
        }
        if let Some(uvs) = &pv.uvs {
            for x in uvs[i] {
                out.write_all(&x.to_le_bytes())?;
            }
        }
        if let Some((_, s)) = options.vertex_scalar {
            out.write_all(&s[v].to_le_bytes())?;
        }
    }
    for f in 0..nf {
        let fv = &pv.face_verts[t.face_offsets[f] as usize..t.face_offsets[f + 1] as usize];
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
/// glTF: the tessellation (with vertex colours, per-face ones split as in OBJ; with
/// `TEXCOORD_0`, vertices split on seams) and, when given, the control mesh's edges as
/// lines.
fn write_glb_tessellation<W: Write>(
    w: &mut W,
    t: &Tessellation,
    colours: Option<Colours>,
    uv: Option<&FaceVarying>,
    options: &TessellationWriteOptions,
) -> io::Result<()> {
    let pv = PerVertex::new(t, colours, uv);
    let rgb: Option<Vec<[f32; 3]>> = pv
        .colours
        .as_ref()
        .map(|c| c.iter().map(|k| k.map(|x| f32::from(x) / 255.0)).collect());
    // glTF's texture origin is the image's top-left corner, OBJ's its bottom-left.
    let texcoords: Option<Vec<[f32; 2]>> = (pv.uvs.as_ref()).map(|uvs| {
        uvs.iter()
            .map(|&[s, t]| [s as f32, (1.0 - t) as f32])
            .collect()
    });
    let edges = options
        .control
        .map(|m| face_edges(m.face_offsets(), m.face_verts()));
    let positions = pv.gather(&t.positions);
    let normals = pv.gather(&t.normals);
    let glb = GlbMesh {
        name: "limit surface",
        positions: &positions,
        normals: Some(&normals),
        colors: rgb.as_deref(),
        texcoords: texcoords.as_deref(),
        face_offsets: &t.face_offsets,
        face_verts: &pv.face_verts,
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
            face_varying: Vec::new(),
        }
    }

    #[test]
    fn per_face_colours_copy_shared_vertices() {
        let t = two_quads();
        let c = PerVertex::new(
            &t,
            Some(Colours::PerFace(&[[255, 0, 0], [0, 0, 255]])),
            None,
        );
        // The shared edge's two vertices are copied: 8 vertices, one colour each.
        assert_eq!(c.num_vertices(), 8);
        assert_eq!(&*c.face_verts, &[0, 1, 2, 3, 4, 5, 6, 7]);
        assert_eq!((c.vertex(1), c.vertex(4)), (1, 1));
        let colours = c.colours.as_deref().unwrap();
        assert_eq!((colours[0], colours[7]), ([255, 0, 0], [0, 0, 255]));
        // Same base face and colour: one run, shared vertices kept shared.
        let mut same = t.clone();
        same.source = vec![(0, 0), (0, 0)];
        let c = PerVertex::new(&same, Some(Colours::PerFace(&[[9, 9, 9], [9, 9, 9]])), None);
        assert_eq!(c.num_vertices(), 6);
    }

    /// `two_quads` with texture coordinates: a seam along the shared edge (vertices 1 and
    /// 4), whose two sides take different values.
    fn two_quads_uv() -> Tessellation {
        let mut t = two_quads();
        let values = vec![
            0.0, 0.0, 0.5, 0.0, 0.5, 1.0, 0.0, 1.0, // left quad
            0.6, 0.0, 1.0, 0.0, 1.0, 1.0, 0.6, 1.0, // right quad
        ];
        let indices = vec![0, 1, 2, 3, 4, 5, 6, 7];
        t.face_varying = vec![FaceVarying::new("uv", 2, values, indices).unwrap()];
        t
    }

    #[test]
    fn seams_split_vertices_per_texture_coordinate() {
        let t = two_quads_uv();
        let c = PerVertex::new(&t, None, t.face_varying.first());
        assert_eq!(c.num_vertices(), 8);
        let uvs = c.uvs.as_ref().unwrap();
        // The seam's vertex 1 is written twice, with (0.5, 0) and (0.6, 0).
        let copies: Vec<[f64; 2]> = (0..8)
            .filter(|&i| c.vertex(i) == 1)
            .map(|i| uvs[i])
            .collect();
        assert_eq!(copies, vec![[0.5, 0.0], [0.6, 0.0]]);
        // Without a seam (the right quad takes the left's values on the shared edge) the
        // vertices stay shared.
        let mut joined = two_quads_uv();
        let values = joined.face_varying[0].values()[..12].to_vec();
        joined.face_varying[0] =
            FaceVarying::new("uv", 2, values, vec![0, 1, 2, 3, 1, 4, 5, 2]).unwrap();
        let c = PerVertex::new(&joined, None, joined.face_varying.first());
        assert_eq!(c.num_vertices(), 6);
        // Per-face colours and texture coordinates together: copies per run and value.
        let both = PerVertex::new(
            &t,
            Some(Colours::PerFace(&[[1, 1, 1]; 2])),
            t.face_varying.first(),
        );
        assert_eq!(both.num_vertices(), 8);
    }

    #[test]
    fn texture_coordinates_in_every_format_but_stl() {
        let t = two_quads_uv();
        let write = |f| {
            let mut out = Vec::new();
            write_tessellation(&mut out, f, &t, &TessellationWriteOptions::default()).unwrap();
            out
        };
        let obj = String::from_utf8(write(TessellationFormat::Obj)).unwrap();
        assert_eq!(obj.matches("\nvt ").count(), 8);
        assert!(obj.contains("f 2/5/2 3/6/3 6/7/6 5/8/5\n"), "{obj}");
        let ply = write(TessellationFormat::Ply);
        let header = String::from_utf8_lossy(
            &ply[..ply.windows(10).position(|w| w == b"end_header").unwrap()],
        )
        .to_string();
        assert!(
            header.contains("element vertex 8\n")
                && header.contains("property double s\nproperty double t\n"),
            "{header}"
        );
        let red = [[255, 0, 0]; 2];
        let coloured = TessellationWriteOptions {
            colours: Some(Colours::PerFace(&red)),
            ..Default::default()
        };
        let mut out = Vec::new();
        write_tessellation(&mut out, TessellationFormat::Obj, &t, &coloured).unwrap();
        let obj = String::from_utf8(out).unwrap();
        assert_eq!(obj.matches("\nvt ").count(), 8);
        assert!(obj.contains("f 5/5/5 6/6/6 7/7/7 8/8/8\n"), "{obj}");
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
