//! glTF 2.0 binary (`.glb`) output, for viewers and browsers.
//!
//! [`write_glb`] writes one self-contained GLB file: a JSON chunk (built with the
//! [`gltf_json`] types) and one BIN chunk holding the buffer. The scene has
//!
//! - a node `"surface"` (or [`GlbMesh::name`]) with a mesh of one `TRIANGLES` primitive:
//!   `POSITION`, optionally `NORMAL` and `COLOR_0`, and `u32` indices; polygons are
//!   triangulated as fans from their first vertex (pass triangles to choose the diagonals
//!   yourself);
//! - optionally a node `"control mesh"` with a mesh of one `LINES` primitive (its own
//!   `POSITION` and `u32` indices), e.g. the edges of the base mesh of a subdivision
//!   surface ([`face_edges`]).
//!
//! # Up axis
//! glTF is `+Y` up (glTF 2.0 specification, section 3.4 "Coordinate System and Units":
//! right-handed, `+Y` up, `+Z` forward). The meshes of this project are `+Z` up
//! (OpenSubdiv's regression shapes, CAD), so by default ([`GlbMesh::up`] `Up::Z`) every
//! position and normal is turned a quarter turn about `X`, `(x, y, z) → (x, z, −y)`: `+Z`
//! becomes `+Y` and `+Y` becomes `−Z`, a rotation (right-handed frames stay right-handed,
//! so faces keep their orientation), and a viewer shows the model standing. A `+Y`-up
//! mesh (`Up::Y`) is written as it is.
//!
//! # Precision
//! glTF stores vertex attributes as **`f32`**: positions and normals are rounded to single
//! precision (about 7 significant digits, a relative error up to 6e-8 of each
//! coordinate), so a GLB file is a lossy copy of the `f64` surface, meant for display; use
//! OBJ or PLY to keep full precision. Normals are normalised before rounding (unit length
//! within 1e-7, as glTF requires); a zero normal (no normal exists there, see
//! [`tessellate`](crate::limit::tessellate)) is written as `+Z`, since glTF allows no
//! zero normals.
//!
//! # Layout
//! The file is the 12-byte header (`glTF`, version 2, total length), the JSON chunk
//! (padded with spaces to a multiple of 4 bytes), then the BIN chunk. The buffer holds, in
//! this order and each in its own buffer view, all tightly packed and so 4-byte aligned:
//! surface positions (`3 × f32` per vertex), normals, colours (`3 × f32`), triangle
//! indices (`u32`), control-mesh positions and line indices (`u32`). `POSITION` accessors
//! carry `min` and `max` (of the `f32` values), as the specification requires.
//!
//! Names (of nodes, meshes, materials and the scene) are added to the JSON after
//! serialisation, so that this module builds with `gltf-json`'s `names` feature off (with
//! it on, the types gain `name` fields that struct literals here would have to set).

use std::collections::HashSet;
use std::io::{self, Write};

use gltf_json as json;
use json::accessor::{ComponentType, GenericComponentType, Type};
use json::buffer::{Target, View};
use json::material::{PbrBaseColorFactor, PbrMetallicRoughness, StrengthFactor};
use json::mesh::{Mode, Primitive, Semantic};
use json::validation::{Checked, USize64};
use json::{Accessor, Buffer, Index, Material, Mesh, Node, Root, Scene};
use serde_json::Value;

use super::Up;

/// GLB magic, `glTF` read as a little-endian `u32`.
pub(crate) const GLB_MAGIC: u32 = 0x4654_6C67;
/// Chunk type of the JSON chunk (`JSON`).
pub const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary chunk (`BIN\0`).
pub const CHUNK_BIN: u32 = 0x004E_4942;

/// Name of the surface node when [`GlbMesh::name`] is empty.
pub(crate) const SURFACE_NAME: &str = "surface";
/// Name of the control-mesh node.
pub(crate) const CONTROL_MESH_NAME: &str = "control mesh";

/// A polygon surface, and optionally line segments drawn with it, to write with
/// [`write_glb`]. All slices are borrowed; nothing is copied until written.
#[derive(Clone, Copy, Debug, Default)]
pub struct GlbMesh<'a> {
    /// Name of the surface node and mesh (empty: `"surface"`).
    pub name: &'a str,
    /// Vertex positions.
    pub positions: &'a [[f64; 3]],
    /// One normal per vertex (normalised when written).
    pub normals: Option<&'a [[f64; 3]]>,
    /// One linear RGB colour per vertex, each component in `[0, 1]` (`COLOR_0`).
    pub colors: Option<&'a [[f32; 3]]>,
    /// One texture coordinate per vertex (`TEXCOORD_0`), in glTF's convention: the image's
    /// origin at its top-left corner, so OBJ's `vt s t` is `[s, 1 − t]` here.
    pub texcoords: Option<&'a [[f32; 2]]>,
    /// CSR face offsets: face `f` has the vertices
    /// `face_verts[face_offsets[f] .. face_offsets[f + 1]]` (at least 3, in
    /// counter-clockwise order seen from the front).
    pub face_offsets: &'a [u32],
    /// CSR face-vertex indices.
    pub face_verts: &'a [u32],
    /// Line segments written as a second node, `"control mesh"`.
    pub control: Option<GlbLines<'a>>,
    /// Which axis of `positions` (and `normals`, and the control mesh's positions) points
    /// up: `Z` (the default) is turned to glTF's `+Y` (module docs, "Up axis").
    pub up: Up,
}

/// `p` in glTF's frame, for a mesh whose up axis is `up` (module docs).
pub fn to_gltf_frame(p: [f64; 3], up: Up) -> [f64; 3] {
    match up {
        Up::Z => [p[0], p[2], -p[1]],
        Up::Y => p,
    }
}

/// Line segments with their own vertices (a `LINES` primitive).
#[derive(Clone, Copy, Debug, Default)]
pub struct GlbLines<'a> {
    /// Vertex positions.
    pub positions: &'a [[f64; 3]],
    /// Segments, as pairs of indices into `positions`.
    pub lines: &'a [[u32; 2]],
}

/// The distinct undirected edges of CSR faces, in order of first appearance (each as the
/// pair in which it first appears), e.g. for [`GlbLines::lines`].
///
/// # Panics
/// If `face_offsets` does not index into `face_verts`.
pub fn face_edges(face_offsets: &[u32], face_verts: &[u32]) -> Vec<[u32; 2]> {
    let mut seen = HashSet::new();
    let mut edges = Vec::new();
    for w in face_offsets.windows(2) {
        let fv = &face_verts[w[0] as usize..w[1] as usize];
        for (i, &a) in fv.iter().enumerate() {
            let b = fv[(i + 1) % fv.len()];
            if a != b && seen.insert((a.min(b), a.max(b))) {
                edges.push([a, b]);
            }
        }
    }
    edges
}

/// Writes `mesh` as a binary glTF 2.0 file (see the module docs).
///
/// # Errors
/// Errors of `w`; [`io::ErrorKind::InvalidInput`] when the CSR arrays are inconsistent, a
/// face has fewer than 3 vertices, an index is out of range, `normals` or `colors` do not
/// have one entry per vertex, a colour is outside `[0, 1]`, there is no face, or the file
/// would exceed GLB's 4 GiB; [`io::ErrorKind::InvalidData`] for a non-finite value or a
/// coordinate beyond the `f32` range.
pub fn write_glb<W: Write>(w: &mut W, mesh: &GlbMesh) -> io::Result<()> {
    let checked = check_glb(mesh)?;
    let (views, bin_len) = buffer_views(mesh, &checked);
    let root = gltf_root(mesh, &checked, &views, bin_len);
    let text = json_chunk(root, mesh, checked.control.is_some())?;
    write_chunks(w, mesh, &checked, &text, bin_len)
}

/// What [`check_glb`] found: the triangle count and the `f32` bounds of the surface and of the
/// control lines, if any.
struct GlbChecked<'a> {
    num_triangles: u64,
    bounds: ([f32; 3], [f32; 3]),
    /// The control lines, when there are any.
    control: Option<GlbLines<'a>>,
    control_bounds: Option<([f32; 3], [f32; 3])>,
}

/// Checks `mesh` for everything [`write_glb`] refuses (see its errors) before anything is
/// written.
fn check_glb<'a>(mesh: &GlbMesh<'a>) -> io::Result<GlbChecked<'a>> {
    let nv = mesh.positions.len();
    super::ply::check_faces(nv, mesh.face_offsets, mesh.face_verts, usize::MAX)?;
    let num_triangles: u64 = mesh
        .face_offsets
        .windows(2)
        .map(|f| u64::from(f[1] - f[0]) - 2)
        .sum();
    if num_triangles == 0 {
        return Err(invalid_input("no faces to write: glTF needs at least one"));
    }
    let bounds = f32_bounds(mesh.positions, mesh.up, "vertex")?;
    if let Some(n) = mesh.normals {
        check_len(n.len(), nv, "normals")?;
        if let Some(i) = n.iter().position(|n| !n.iter().all(|c| c.is_finite())) {
            return Err(invalid_data(format!(
                "the normal of vertex {i} is not finite ({:?})",
                n[i]
            )));
        }
    }
    if let Some(c) = mesh.colors {
        check_len(c.len(), nv, "colors")?;
        if let Some(i) = c
            .iter()
            .position(|c| !c.iter().all(|x| (0.0..=1.0).contains(x)))
        {
            return Err(invalid_input(format!(
                "the colour of vertex {i} is outside [0, 1] ({:?})",
                c[i]
            )));
        }
    }
    if let Some(t) = mesh.texcoords {
        check_len(t.len(), nv, "texture coordinates")?;
        if let Some(i) = t.iter().position(|t| !t.iter().all(|x| x.is_finite())) {
            return Err(invalid_data(format!(
                "the texture coordinate of vertex {i} is not finite ({:?})",
                t[i]
            )));
        }
    }
    let control = mesh.control.filter(|c| !c.lines.is_empty());
    let control_bounds = match control {
        Some(c) => {
            let n = c.positions.len();
            if let Some((i, l)) = c
                .lines
                .iter()
                .enumerate()
                .find(|(_, l)| l.iter().any(|&v| v as usize >= n))
            {
                return Err(invalid_input(format!(
                    "control line {i} refers to vertex {} of {n}",
                    l[0].max(l[1])
                )));
            }
            Some(f32_bounds(c.positions, mesh.up, "control vertex")?)
        }
        None => None,
    };
    Ok(GlbChecked {
        num_triangles,
        bounds,
        control,
        control_bounds,
    })
}

/// The buffer views' lengths and targets, in buffer order (positions, normals, colours,
/// texture coordinates, triangle indices, control positions, control line indices), and the BIN chunk's length.
fn buffer_views(mesh: &GlbMesh, checked: &GlbChecked) -> (Vec<(u64, Target)>, u64) {
    let vec3 = 12 * mesh.positions.len() as u64;
    let mut views = vec![(vec3, Target::ArrayBuffer)];
    if mesh.normals.is_some() {
        views.push((vec3, Target::ArrayBuffer));
    }
    if mesh.colors.is_some() {
        views.push((vec3, Target::ArrayBuffer));
    }
    if mesh.texcoords.is_some() {
        views.push((8 * mesh.positions.len() as u64, Target::ArrayBuffer));
    }
    views.push((12 * checked.num_triangles, Target::ElementArrayBuffer));
    if let Some(c) = checked.control {
        views.push((12 * c.positions.len() as u64, Target::ArrayBuffer));
        views.push((8 * c.lines.len() as u64, Target::ElementArrayBuffer));
    }
    let bin_len: u64 = views.iter().map(|v| v.0).sum();
    (views, bin_len)
}

/// The glTF document: one buffer of `bin_len` bytes cut into `views`, the surface's mesh and
/// node, the control lines' mesh and node if any, and a scene holding them.
fn gltf_root(mesh: &GlbMesh, checked: &GlbChecked, views: &[(u64, Target)], bin_len: u64) -> Root {
    let mut root = Root {
        asset: json::Asset {
            generator: Some(format!("subsurf {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let buffer = root.push(Buffer {
        byte_length: USize64(bin_len),
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let mut offset = 0;
    let mut accessors = Vec::new();
    for &(len, target) in views {
        let view = root.push(View {
            buffer,
            byte_length: USize64(len),
            byte_offset: Some(USize64(offset)),
            byte_stride: None,
            target: Some(Checked::Valid(target)),
            extensions: None,
            extras: Default::default(),
        });
        offset += len;
        accessors.push(view);
    }
    let mut views = accessors.into_iter();
    let mut next_view = || views.next().expect("one view per accessor");
    let surface_node = push_surface(&mut root, mesh, checked, &mut next_view);
    let mut nodes = vec![surface_node];
    if let (Some(c), Some(b)) = (checked.control, checked.control_bounds) {
        nodes.push(push_control(&mut root, c, b, &mut next_view));
    }
    root.scene = Some(root.push(Scene {
        extensions: None,
        extras: Default::default(),
        nodes,
    }));
    root
}

/// Pushes the surface's accessors (positions with their bounds, normals, colours, triangle
/// indices), material, mesh and node onto `root`; returns the node.
fn push_surface(
    root: &mut Root,
    mesh: &GlbMesh,
    checked: &GlbChecked,
    next_view: &mut impl FnMut() -> Index<View>,
) -> Index<Node> {
    let nv = mesh.positions.len();
    let position = root.push(accessor(next_view(), nv, Type::Vec3, ComponentType::F32));
    set_bounds(&mut root.accessors[position.value()], checked.bounds);
    let mut attributes = vec![(Semantic::Positions, position)];
    if mesh.normals.is_some() {
        let a = accessor(next_view(), nv, Type::Vec3, ComponentType::F32);
        attributes.push((Semantic::Normals, root.push(a)));
    }
    if mesh.colors.is_some() {
        let a = accessor(next_view(), nv, Type::Vec3, ComponentType::F32);
        attributes.push((Semantic::Colors(0), root.push(a)));
    }
    if mesh.texcoords.is_some() {
        let a = accessor(next_view(), nv, Type::Vec2, ComponentType::F32);
        attributes.push((Semantic::TexCoords(0), root.push(a)));
    }
    let count = 3 * checked.num_triangles as usize;
    let indices = root.push(accessor(
        next_view(),
        count,
        Type::Scalar,
        ComponentType::U32,
    ));
    let surface_material = root.push(material([0.8, 0.8, 0.8, 1.0], mesh.colors.is_some(), false));
    let surface_mesh = root.push(Mesh {
        extensions: None,
        extras: Default::default(),
        primitives: vec![primitive(
            attributes,
            indices,
            surface_material,
            Mode::Triangles,
        )],
        weights: None,
    });
    root.push(Node {
        mesh: Some(surface_mesh),
        ..Default::default()
    })
}

/// Pushes the control lines' accessors (positions with `bounds`, line indices), material,
/// mesh and node onto `root`; returns the node.
fn push_control(
    root: &mut Root,
    c: GlbLines,
    bounds: ([f32; 3], [f32; 3]),
    next_view: &mut impl FnMut() -> Index<View>,
) -> Index<Node> {
    let np = c.positions.len();
    let position = root.push(accessor(next_view(), np, Type::Vec3, ComponentType::F32));
    set_bounds(&mut root.accessors[position.value()], bounds);
    let count = 2 * c.lines.len();
    let indices = root.push(accessor(
        next_view(),
        count,
        Type::Scalar,
        ComponentType::U32,
    ));
    let m = root.push(material([0.05, 0.05, 0.05, 1.0], false, true));
    let lines = root.push(Mesh {
        extensions: None,
        extras: Default::default(),
        primitives: vec![primitive(
            vec![(Semantic::Positions, position)],
            indices,
            m,
            Mode::Lines,
        )],
        weights: None,
    });
    root.push(Node {
        mesh: Some(lines),
        ..Default::default()
    })
}

/// The JSON chunk's text: `root` with the scene, nodes, meshes and materials named, padded
/// with spaces to a multiple of 4 bytes.
fn json_chunk(root: Root, mesh: &GlbMesh, control: bool) -> io::Result<Vec<u8>> {
    let mut value = root.to_value().map_err(io::Error::other)?;
    let surface_name = if mesh.name.is_empty() {
        SURFACE_NAME
    } else {
        mesh.name
    };
    name(&mut value, "scenes", 0, "subsurf");
    name(&mut value, "nodes", 0, surface_name);
    name(&mut value, "meshes", 0, surface_name);
    name(&mut value, "materials", 0, "surface");
    if control {
        name(&mut value, "nodes", 1, CONTROL_MESH_NAME);
        name(&mut value, "meshes", 1, CONTROL_MESH_NAME);
        name(&mut value, "materials", 1, CONTROL_MESH_NAME);
    }
    let mut text = serde_json::to_vec(&value).map_err(io::Error::other)?;
    text.resize(text.len().next_multiple_of(4), b' ');
    Ok(text)
}

/// Writes the GLB header, the JSON chunk `text` and the BIN chunk (`bin_len` bytes: the data
/// of the views of [`buffer_views`], in their order) to `w`; refuses a file over 4 GiB.
fn write_chunks<W: Write>(
    w: &mut W,
    mesh: &GlbMesh,
    checked: &GlbChecked,
    text: &[u8],
    bin_len: u64,
) -> io::Result<()> {
    let total = 12 + 8 + text.len() as u64 + 8 + bin_len;
    if total > u64::from(u32::MAX) {
        return Err(invalid_input(format!(
            "the GLB file would have {total} bytes; the format allows at most {}",
            u32::MAX
        )));
    }
    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK + text.len() + 64);
    for x in [GLB_MAGIC, 2, total as u32, text.len() as u32, CHUNK_JSON] {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    buf.extend_from_slice(text);
    for x in [bin_len as u32, CHUNK_BIN] {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    let mut out = Body { buf, w };
    let turn = |p: &[f64; 3]| to_gltf_frame(*p, mesh.up);
    for p in mesh.positions {
        out.vec3(turn(p).map(|c| c as f32))?;
    }
    if let Some(normals) = mesh.normals {
        for n in normals {
            out.vec3(unit_f32(&turn(n)))?;
        }
    }
    if let Some(colors) = mesh.colors {
        for &c in colors {
            out.vec3(c)?;
        }
    }
    if let Some(texcoords) = mesh.texcoords {
        for t in texcoords {
            out.f32s(t)?;
        }
    }
    for f in mesh.face_offsets.windows(2) {
        let fv = &mesh.face_verts[f[0] as usize..f[1] as usize];
        for k in 1..fv.len() - 1 {
            out.u32s(&[fv[0], fv[k], fv[k + 1]])?;
        }
    }
    if let Some(c) = checked.control {
        for p in c.positions {
            out.vec3(turn(p).map(|c| c as f32))?;
        }
        for l in c.lines {
            out.u32s(l)?;
        }
    }
    // Every view is a multiple of 4 bytes long, so the BIN chunk needs no padding.
    out.finish()
}

/// The `f32` bounds (`min`, `max`) of `positions` in glTF's frame ([`to_gltf_frame`]).
fn f32_bounds(positions: &[[f64; 3]], up: Up, what: &str) -> io::Result<([f32; 3], [f32; 3])> {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for (i, p) in positions.iter().enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(invalid_data(format!(
                "{what} {i} has a non-finite coordinate ({}, {}, {})",
                p[0], p[1], p[2]
            )));
        }
        let p = to_gltf_frame(*p, up);
        for k in 0..3 {
            let c = p[k] as f32;
            if !c.is_finite() {
                return Err(invalid_data(format!(
                    "{what} {i} has a coordinate beyond the f32 range of glTF ({})",
                    p[k].abs()
                )));
            }
            lo[k] = lo[k].min(c);
            hi[k] = hi[k].max(c);
        }
    }
    if positions.is_empty() {
        return Ok(([0.0; 3], [0.0; 3]));
    }
    Ok((lo, hi))
}

/// `n` normalised, in `f32`; `+Z` for a zero vector.
fn unit_f32(n: &[f64; 3]) -> [f32; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|c| (c / len) as f32)
    } else {
        [0.0, 0.0, 1.0]
    }
}

fn accessor(view: Index<View>, count: usize, ty: Type, ct: ComponentType) -> Accessor {
    Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(count),
        component_type: Checked::Valid(GenericComponentType(ct)),
        extensions: None,
        extras: Default::default(),
        type_: Checked::Valid(ty),
        min: None,
        max: None,
        normalized: false,
        sparse: None,
    }
}

fn set_bounds(a: &mut Accessor, (lo, hi): ([f32; 3], [f32; 3])) {
    let v = |x: [f32; 3]| Value::from(x.map(f64::from).to_vec());
    a.min = Some(v(lo));
    a.max = Some(v(hi));
}

fn material(color: [f32; 4], white: bool, lines: bool) -> Material {
    Material {
        pbr_metallic_roughness: PbrMetallicRoughness {
            // Vertex colours multiply the base colour.
            base_color_factor: PbrBaseColorFactor(if white { [1.0; 4] } else { color }),
            metallic_factor: StrengthFactor(0.0),
            roughness_factor: StrengthFactor(if lines { 1.0 } else { 0.5 }),
            ..Default::default()
        },
        double_sided: !lines,
        ..Default::default()
    }
}

fn primitive(
    attributes: Vec<(Semantic, Index<Accessor>)>,
    indices: Index<Accessor>,
    material: Index<Material>,
    mode: Mode,
) -> Primitive {
    Primitive {
        attributes: attributes
            .into_iter()
            .map(|(s, a)| (Checked::Valid(s), a))
            .collect(),
        extensions: None,
        extras: Default::default(),
        indices: Some(indices),
        material: Some(material),
        mode: Checked::Valid(mode),
        targets: None,
    }
}

/// Sets `"name"` of `json[list][i]`.
fn name(json: &mut Value, list: &str, i: usize, name: &str) {
    if let Some(Value::Object(o)) = json.get_mut(list).and_then(|l| l.get_mut(i)) {
        o.insert("name".into(), Value::from(name));
    }
}

/// Bytes gathered before handing them to the writer.
const CHUNK: usize = 1 << 16;

/// The buffer's bytes on their way to the writer.
struct Body<'w, W: Write> {
    buf: Vec<u8>,
    w: &'w mut W,
}

impl<W: Write> Body<'_, W> {
    fn vec3(&mut self, v: [f32; 3]) -> io::Result<()> {
        self.f32s(&v)
    }

    fn f32s(&mut self, v: &[f32]) -> io::Result<()> {
        v.iter()
            .for_each(|x| self.buf.extend_from_slice(&x.to_le_bytes()));
        self.flush_full()
    }

    fn u32s(&mut self, v: &[u32]) -> io::Result<()> {
        v.iter()
            .for_each(|x| self.buf.extend_from_slice(&x.to_le_bytes()));
        self.flush_full()
    }

    fn flush_full(&mut self) -> io::Result<()> {
        if self.buf.len() >= CHUNK {
            self.w.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    fn finish(self) -> io::Result<()> {
        self.w.write_all(&self.buf)
    }
}

fn check_len(got: usize, want: usize, what: &str) -> io::Result<()> {
    if got == want {
        Ok(())
    } else {
        Err(invalid_input(format!(
            "{got} {what} given for {want} vertices; glTF needs one per vertex"
        )))
    }
}

fn invalid_input(message: impl Into<String>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message.into())
}

fn invalid_data(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fan_triangulation_and_edges() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 1.5, 0.0],
        ];
        let mesh = GlbMesh {
            positions: &p,
            face_offsets: &[0, 5],
            face_verts: &[0, 1, 2, 4, 3],
            ..Default::default()
        };
        let mut out = Vec::new();
        write_glb(&mut out, &mesh).unwrap();
        let json_len = u32::from_le_bytes(out[12..16].try_into().unwrap()) as usize;
        let bin = &out[20 + json_len + 8..];
        let idx: Vec<u32> = bin[60..]
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        assert_eq!(idx, [0, 1, 2, 0, 2, 4, 0, 4, 3]);
        assert_eq!(
            face_edges(&[0, 4, 7], &[0, 1, 2, 3, 2, 1, 4]),
            [[0, 1], [1, 2], [2, 3], [3, 0], [1, 4], [4, 2]]
        );
    }

    #[test]
    fn rejects_bad_input() {
        let p = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let ok = GlbMesh {
            positions: &p,
            face_offsets: &[0, 3],
            face_verts: &[0, 1, 2],
            ..Default::default()
        };
        let kind = |m: GlbMesh| write_glb(&mut Vec::new(), &m).unwrap_err().kind();
        assert!(write_glb(&mut Vec::new(), &ok).is_ok());
        let empty = GlbMesh {
            face_offsets: &[0],
            face_verts: &[],
            ..ok
        };
        assert_eq!(kind(empty), io::ErrorKind::InvalidInput);
        let out_of_range = GlbMesh {
            face_verts: &[0, 1, 3],
            ..ok
        };
        assert_eq!(kind(out_of_range), io::ErrorKind::InvalidInput);
        let nan = [[0.0; 3], [f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(
            kind(GlbMesh {
                positions: &nan,
                ..ok
            }),
            io::ErrorKind::InvalidData
        );
        let huge = [[0.0; 3], [1e300, 0.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(
            kind(GlbMesh {
                positions: &huge,
                ..ok
            }),
            io::ErrorKind::InvalidData
        );
        let few = [[0.0, 0.0, 1.0]; 2];
        assert_eq!(
            kind(GlbMesh {
                normals: Some(&few),
                ..ok
            }),
            io::ErrorKind::InvalidInput
        );
        let bright = [[0.5, 0.5, 0.5], [0.5, 1.5, 0.5], [0.0; 3]];
        assert_eq!(
            kind(GlbMesh {
                colors: Some(&bright),
                ..ok
            }),
            io::ErrorKind::InvalidInput
        );
        let lines = GlbLines {
            positions: &p,
            lines: &[[0, 3]],
        };
        assert_eq!(
            kind(GlbMesh {
                control: Some(lines),
                ..ok
            }),
            io::ErrorKind::InvalidInput
        );
    }
}
