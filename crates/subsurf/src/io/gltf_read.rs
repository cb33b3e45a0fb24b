//! glTF 2.0 input (`.gltf` with external or embedded buffers, `.glb`): the triangles of
//! a scene as one [`PolyMesh`], welded into a connected control mesh, with `TEXCOORD_0` as
//! the face-varying channel `"uv"`.
//!
//! [`parse_gltf`] reads the JSON with the `gltf` crate, checks every reference that it
//! follows, and reads the buffers itself: the `BIN` chunk of a GLB file, `data:` URIs in base64 and
//! files named by relative URIs, looked up in the directory given (for
//! [`read_mesh`](crate::io::read_mesh), the file's). Every offset, length, stride and index
//! is checked before it is used: bad input is a [`GltfError`] naming the file and the
//! mesh, primitive, accessor, buffer or node, never a panic.
//!
//! # What is read
//! - **Geometry.** Every primitive of every mesh that a node of the default scene (or,
//!   without one, the first scene) reaches, with the node's transform composed down the
//!   hierarchy (a `matrix`, or `translation`, `rotation`, `scale` as `T·R·S`; glTF 2.0
//!   specification, section 3.5.3 "Transformations"); without scenes, every mesh as it is.
//!   A node with a skin is read in its mesh's own space (the specification ignores the
//!   transform of a skinned node). A mirroring transform (negative determinant) reverses
//!   the triangles, so that they stay counter-clockwise seen from outside.
//! - **Faces.** Primitives of mode `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN`
//!   (converted to triangles by the specification's formulas, section 3.7.2.1), indexed or
//!   not; `POINTS` and `LINES` primitives make no faces and are noted. `POSITION` must be
//!   `VEC3` of `f32` (sparse accessors and `KHR_mesh_quantization` are not read); each
//!   is turned into `f64` exactly.
//! - **Welding.** glTF splits vertices wherever a texture coordinate or a normal differs
//!   (a seam), so the triangles of a primitive share no vertex across a seam. A
//!   subdivision surface needs the connected control mesh: vertices with the *same
//!   position* after the transform (bit for bit, `+0` and `−0` alike) are made one vertex,
//!   within a primitive and across the primitives of one mesh instance (a mesh reached by
//!   two nodes gives two unconnected copies). Welding is by exact position only: vertices a
//!   rounding error apart stay apart, and separate parts of a mesh that touch at a vertex
//!   are joined there. A triangle whose corners weld into fewer than three vertices is
//!   dropped, and noted.
//! - **Texture coordinates.** `TEXCOORD_0` (`VEC2` of `f32`, or of normalized `u8` or
//!   `u16`) becomes the face-varying channel `"uv"` ([`FaceVarying`]): each triangle
//!   corner takes the coordinates of its glTF vertex, and corners at one welded vertex
//!   with the same coordinates share one value, so a seam is exactly where the
//!   coordinates differ. glTF puts the origin of a texture at its top-left corner (`v`
//!   down), OBJ (and OpenSubdiv's examples) at the bottom-left: values are stored as
//!   `(s, t) = (u, 1 − v)`, OBJ's convention, so that an OBJ file written from the mesh
//!   maps the texture as the glTF file did. If some primitives read have `TEXCOORD_0` and
//!   others not, the mesh gets no channel (noted).
//! - **Up axis.** glTF is `+Y` up; this project's meshes are `+Z` up
//!   ([`Up`], the default of the renderer and of the glTF writer, which turns `+Z` up to
//!   glTF's `+Y`). With `up` [`Up::Z`] positions are turned from glTF's frame by the
//!   inverse of the writer's quarter turn, `(x, y, z) → (x, −z, y)` (exact: a permutation
//!   and a sign), so that writing the mesh to glTF again gives back the glTF positions;
//!   with [`Up::Y`] they are kept as they are.
//!
//! # What is not read (noted in [`GltfFile::ignored`], one line per kind)
//! Normals, tangents, colours, texture coordinates other than `TEXCOORD_0`, joints and
//! weights, custom attributes, morph targets, materials, textures, skins, animations,
//! cameras, other scenes, meshes that no node of the scene reaches.

mod data;

use std::collections::HashMap;
use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use gltf::scene::Transform;
use gltf::{Document, Semantic};
use serde_json::Value;

use super::Up;
use crate::mesh::{FaceVarying, PolyMesh, MAX_COORDINATE};
use data::{elements, split_glb, BufferError, Buffers};

/// An error reading glTF: the file and what is wrong (naming the mesh, primitive,
/// accessor, buffer or node).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{source_name}: {message}")]
pub struct GltfError {
    /// File name as given (or `<stdin>`).
    pub source_name: String,
    /// What is wrong.
    pub message: String,
}

/// A mesh read from a glTF file by [`parse_gltf`].
#[derive(Clone, Debug, PartialEq)]
pub struct GltfFile {
    /// Every triangle read, welded (module docs), with the channel `"uv"` when the
    /// primitives have `TEXCOORD_0`.
    pub mesh: PolyMesh,
    /// Whether the file was binary glTF (`.glb`).
    pub binary: bool,
    /// What the file holds and the mesh leaves out, one line per kind (module docs).
    pub ignored: Vec<String>,
}

/// Why [`parse_gltf_within`] gave no mesh.
#[derive(Debug)]
pub(crate) enum Refusal {
    /// The file is not glTF that can be read.
    Gltf(GltfError),
    /// Holding the file, its buffers and the mesh would take about `needed` bytes, more
    /// than the limit.
    TooLarge { needed: u64 },
}

/// Reads the glTF 2.0 file `bytes` (JSON or binary; `name` in messages): see the module
/// docs. Relative buffer URIs are looked up in `dir` (the current directory without it);
/// positions are turned to the up axis `up`.
///
/// # Errors
/// [`GltfError`] naming the file and what is at fault: a GLB container cut short, JSON
/// that is not glTF or refers to things that do not exist, a buffer without data, an
/// accessor of the wrong type or beyond its buffer, an index beyond the vertices, a
/// primitive without `POSITION`, a non-finite coordinate or one of 1e75 or more, a node
/// hierarchy that is not a tree, or no triangle at all.
pub fn parse_gltf(
    bytes: &[u8],
    name: &str,
    dir: Option<&Path>,
    up: Up,
) -> Result<GltfFile, GltfError> {
    parse_gltf_within(bytes, name, dir, up, None).map_err(|r| match r {
        Refusal::Gltf(e) => e,
        Refusal::TooLarge { .. } => unreachable!("no memory limit was given"),
    })
}

/// [`parse_gltf`], refused when the file, its external buffers and the mesh read from
/// them would need more than `limit` bytes (about 72 bytes per vertex and 28 per triangle
/// corner read, counted from the accessors before they are read; the buffer files by
/// their sizes, before each is read).
pub(crate) fn parse_gltf_within(
    bytes: &[u8],
    name: &str,
    dir: Option<&Path>,
    up: Up,
    limit: Option<u64>,
) -> Result<GltfFile, Refusal> {
    let fail = |message: String| {
        Refusal::Gltf(GltfError {
            source_name: name.to_owned(),
            message,
        })
    };
    let binary = bytes.starts_with(b"glTF");
    let (json, bin) = match binary {
        true => split_glb(bytes).map_err(fail)?,
        false => (bytes, None),
    };
    let mut notes = Notes::default();
    let doc = document(json, &mut notes).map_err(fail)?;
    let instances = instances(&doc, &mut notes).map_err(fail)?;
    let needed = (bytes.len() as u64).saturating_add(list_bytes(&doc, &instances));
    if limit.is_some_and(|l| needed > l) {
        return Err(Refusal::TooLarge { needed });
    }
    let room = limit.map(|l| l.saturating_sub(needed));
    let mut buffers = Buffers::new(doc.buffers().count(), bin, dir, room);
    let mut builder = Builder::new(up);
    for instance in &instances {
        builder
            .instance(&doc, instance, &mut buffers, &mut notes)
            .map_err(|e| match e {
                BufferError::Bad(m) => fail(m),
                BufferError::TooLarge { needed: files } => Refusal::TooLarge {
                    needed: needed.saturating_add(files),
                },
            })?;
    }
    notes.document(&doc);
    let mesh = builder.finish(&mut notes).map_err(fail)?;
    Ok(GltfFile {
        mesh,
        binary,
        ignored: notes.lines(),
    })
}

/// The document in `json`, parsed by the `gltf` crate and checked by
/// [`check_references`]; custom attributes (`_NAME`, which the crate does not know) are
/// taken out first, and noted.
fn document(json: &[u8], notes: &mut Notes) -> Result<Document, String> {
    let mut value: Value =
        serde_json::from_slice(json).map_err(|e| format!("not valid glTF JSON: {e}"))?;
    if value.get("asset").is_none() {
        return Err("not a glTF file: its JSON has no \"asset\"".into());
    }
    let meshes = value.get_mut("meshes").and_then(Value::as_array_mut);
    let prims = (meshes.into_iter().flatten())
        .filter_map(|m| m.get_mut("primitives").and_then(Value::as_array_mut))
        .flatten();
    for p in prims.filter_map(Value::as_object_mut) {
        let mut maps: Vec<&mut Value> = Vec::new();
        for (k, v) in p.iter_mut() {
            match (k.as_str(), v) {
                ("attributes", v) => maps.push(v),
                ("targets", Value::Array(t)) => maps.extend(t.iter_mut()),
                _ => {}
            }
        }
        for map in maps.into_iter().filter_map(Value::as_object_mut) {
            let before = map.len();
            map.retain(|k, _| !k.starts_with('_'));
            if map.len() < before {
                notes.add(Note::Custom);
            }
        }
    }
    let root: gltf::json::Root =
        serde_json::from_value(value).map_err(|e| format!("not valid glTF JSON: {e}"))?;
    check_references(&root)?;
    Ok(Document::from_json_without_validation(root))
}

/// Checks what the reading follows in `root`: every index in range (scene, nodes,
/// children, meshes, skins, accessors, buffer views, buffers), every enumerated value known
/// (attribute names, modes, component types, accessor types), and no required extension
/// that changes geometry or texture coordinates. (The `gltf` crate's own validation
/// refuses files that this reader can read, such as `POSITION` accessors without `min`
/// and `max`, and can panic on an accessor index out of range.)
fn check_references(root: &gltf::json::Root) -> Result<(), String> {
    use gltf::json::validation::Checked;
    let range = |what: &str, at: String, i: usize, n: usize| match i < n {
        true => Ok(()),
        false => Err(format!("{at} refers to {what} {i}, but the file has {n}")),
    };
    for ext in &root.extensions_required {
        if !(ext.starts_with("KHR_materials_") || ext == "KHR_lights_punctual") {
            return Err(format!(
                "the file requires the extension {ext}, which is not read"
            ));
        }
    }
    let (nodes, meshes, accessors) = (root.nodes.len(), root.meshes.len(), root.accessors.len());
    if let Some(s) = root.scene {
        range(
            "scene",
            "the default scene".into(),
            s.value(),
            root.scenes.len(),
        )?;
    }
    for (i, scene) in root.scenes.iter().enumerate() {
        for n in &scene.nodes {
            range("node", format!("scene {i}"), n.value(), nodes)?;
        }
    }
    for (i, node) in root.nodes.iter().enumerate() {
        for c in node.children.iter().flatten() {
            range("node", format!("node {i}"), c.value(), nodes)?;
        }
        if let Some(m) = node.mesh {
            range("mesh", format!("node {i}"), m.value(), meshes)?;
        }
        if let Some(k) = node.skin {
            range("skin", format!("node {i}"), k.value(), root.skins.len())?;
        }
    }
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let at = || format!("mesh {m}, primitive {p}");
            if matches!(prim.mode, Checked::Invalid) {
                return Err(format!("{}: its mode is not one of glTF's", at()));
            }
            let targets = prim.targets.iter().flatten();
            let morphs = targets
                .flat_map(|t| [t.positions, t.normals, t.tangents])
                .flatten();
            for a in prim
                .attributes
                .values()
                .chain(&prim.indices)
                .copied()
                .chain(morphs)
            {
                range("accessor", at(), a.value(), accessors)?;
            }
            if prim
                .attributes
                .keys()
                .any(|k| matches!(k, Checked::Invalid))
            {
                return Err(format!("{}: an attribute name is not one of glTF's", at()));
            }
        }
    }
    for (i, a) in root.accessors.iter().enumerate() {
        if matches!(a.component_type, Checked::Invalid) || matches!(a.type_, Checked::Invalid) {
            return Err(format!(
                "accessor {i}: its componentType or type is not one of glTF's"
            ));
        }
        if let Some(v) = a.buffer_view {
            range(
                "buffer view",
                format!("accessor {i}"),
                v.value(),
                root.buffer_views.len(),
            )?;
        }
    }
    for (i, v) in root.buffer_views.iter().enumerate() {
        range(
            "buffer",
            format!("buffer view {i}"),
            v.buffer.value(),
            root.buffers.len(),
        )?;
    }
    Ok(())
}

/// A 4 × 4 matrix, column-major as glTF stores them: `m[column][row]`.
type Matrix = [[f64; 4]; 4];

const IDENTITY: Matrix = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// A mesh placed by a node: its index, the node (none without scenes) and the node's
/// global transform.
struct Instance {
    mesh: usize,
    node: Option<usize>,
    matrix: Matrix,
}

/// The meshes of the default scene (or the first; every mesh without scenes), with their
/// global transforms, in the order of a depth-first walk of the scene's nodes.
///
/// # Errors
/// A node reached twice (the hierarchy must be a set of trees), a transform that is not
/// finite.
fn instances(doc: &Document, notes: &mut Notes) -> Result<Vec<Instance>, String> {
    let Some(scene) = doc.default_scene().or_else(|| doc.scenes().next()) else {
        let all = doc.meshes().map(|m| Instance {
            mesh: m.index(),
            node: None,
            matrix: IDENTITY,
        });
        return Ok(all.collect());
    };
    for _ in 1..doc.scenes().count() {
        notes.add(Note::OtherScene);
    }
    let mut seen = vec![false; doc.nodes().count()];
    let mut stack: Vec<(gltf::Node<'_>, Matrix)> = scene.nodes().map(|n| (n, IDENTITY)).collect();
    stack.reverse();
    let mut out = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        let i = node.index();
        match seen.get_mut(i) {
            Some(s) if !*s => *s = true,
            _ => {
                return Err(format!(
                    "node {i} is reached twice from scene {}: a node may have one parent \
                     only, and no node may be its own ancestor",
                    scene.index()
                ))
            }
        }
        let local = local_matrix(node.transform());
        if local.iter().flatten().any(|x| !x.is_finite()) {
            return Err(format!("node {i}: its transform is not finite"));
        }
        let global = multiply(&parent, &local);
        if let Some(mesh) = node.mesh() {
            let skinned = node.skin().is_some();
            out.push(Instance {
                mesh: mesh.index(),
                node: Some(i),
                matrix: if skinned { IDENTITY } else { global },
            });
        }
        let children: Vec<_> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, global)));
    }
    let mut used = vec![false; doc.meshes().count()];
    for m in &out {
        used[m.mesh] = true;
    }
    for _ in used.iter().filter(|&&u| !u) {
        notes.add(Note::MeshOutsideScene);
    }
    Ok(out)
}

/// A node's local transform as a matrix: its `matrix`, or `T·R·S` of its translation,
/// rotation (a unit quaternion `x, y, z, w`) and scale.
fn local_matrix(t: Transform) -> Matrix {
    match t {
        Transform::Matrix { matrix } => matrix.map(|c| c.map(f64::from)),
        Transform::Decomposed {
            translation: t,
            rotation: q,
            scale: s,
        } => {
            let [x, y, z, w] = q.map(f64::from);
            let r = [
                [
                    1.0 - 2.0 * (y * y + z * z),
                    2.0 * (x * y + w * z),
                    2.0 * (x * z - w * y),
                ],
                [
                    2.0 * (x * y - w * z),
                    1.0 - 2.0 * (x * x + z * z),
                    2.0 * (y * z + w * x),
                ],
                [
                    2.0 * (x * z + w * y),
                    2.0 * (y * z - w * x),
                    1.0 - 2.0 * (x * x + y * y),
                ],
            ];
            let mut m = IDENTITY;
            for c in 0..3 {
                for row in 0..3 {
                    m[c][row] = r[c][row] * f64::from(s[c]);
                }
                m[3][c] = f64::from(t[c]);
            }
            m
        }
    }
}

fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    if *a == IDENTITY {
        return *b;
    }
    let mut m = [[0.0; 4]; 4];
    for (c, col) in m.iter_mut().enumerate() {
        for (r, x) in col.iter_mut().enumerate() {
            *x = (0..4).map(|k| a[k][r] * b[c][k]).sum();
        }
    }
    m
}

/// The determinant of the upper-left 3 × 3 block: negative for a mirroring transform.
fn determinant3(m: &Matrix) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2])
        - m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2])
        + m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2])
}

/// `p` moved by the affine matrix `m` (exactly `p` for the identity).
fn transform(m: &Matrix, p: [f64; 3]) -> [f64; 3] {
    if *m == IDENTITY {
        return p;
    }
    [0, 1, 2].map(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

/// `p` of glTF's `+Y`-up frame in a frame whose up axis is `up` (module docs): the inverse
/// of [`to_gltf_frame`](crate::io::to_gltf_frame).
pub fn from_gltf_frame(p: [f64; 3], up: Up) -> [f64; 3] {
    match up {
        Up::Z => [p[0], -p[2], p[1]],
        Up::Y => p,
    }
}

/// The bytes of the lists built from the triangle primitives of `instances` (positions,
/// welding and texture coordinates per vertex, faces and their values per corner), from
/// their accessors' counts, before any is read.
fn list_bytes(doc: &Document, instances: &[Instance]) -> u64 {
    let mut bytes = 0u64;
    for instance in instances {
        let Some(mesh) = doc.meshes().nth(instance.mesh) else {
            continue;
        };
        for prim in mesh.primitives().filter(|p| triangles_mode(p.mode())) {
            let vertices = prim.get(&Semantic::Positions).map_or(0, |a| a.count()) as u64;
            let corners = prim.indices().map_or(vertices, |a| a.count() as u64);
            bytes = bytes
                .saturating_add(vertices.saturating_mul(72))
                .saturating_add(corners.saturating_mul(28));
        }
    }
    bytes
}

/// Whether primitives of `mode` make triangles.
fn triangles_mode(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

/// The triangles of `n` vertices (or indices) in `mode`, as positions in that list
/// (glTF 2.0 specification, section 3.7.2.1: strips `(i, i + 1 + i % 2, i + 2 − i % 2)`,
/// fans `(i + 1, i + 2, 0)`).
///
/// # Errors
/// `TRIANGLES` of a count that is not a multiple of 3.
fn triangles(mode: Mode, n: usize) -> Result<Vec<[usize; 3]>, String> {
    Ok(match mode {
        Mode::Triangles if !n.is_multiple_of(3) => {
            return Err(format!(
                "its {n} vertices do not make whole triangles (mode TRIANGLES needs a multiple                  of 3)"
            ))
        }
        Mode::Triangles => (0..n / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| [i, i + 1 + i % 2, i + 2 - i % 2])
            .collect(),
        _ => (0..n.saturating_sub(2)).map(|i| [i + 1, i + 2, 0]).collect(),
    })
}

/// Kinds of things read and left out, for one note each.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Note {
    Normals,
    Tangents,
    Colours,
    OtherTexcoords,
    JointsWeights,
    Custom,
    MorphTargets,
    PointsLines,
    Degenerate,
    TexcoordsDropped,
    Materials,
    Textures,
    Skins,
    Animations,
    Cameras,
    OtherScene,
    MeshOutsideScene,
}

/// How many of each [`Note`].
#[derive(Default)]
struct Notes {
    counts: std::collections::BTreeMap<Note, usize>,
}

impl Notes {
    fn add(&mut self, note: Note) {
        self.add_n(note, 1);
    }

    fn add_n(&mut self, note: Note, n: usize) {
        if n > 0 {
            *self.counts.entry(note).or_default() += n;
        }
    }

    /// What the document holds besides meshes.
    fn document(&mut self, doc: &Document) {
        self.add_n(Note::Materials, doc.materials().count());
        self.add_n(Note::Textures, doc.textures().count());
        self.add_n(Note::Skins, doc.skins().count());
        self.add_n(Note::Animations, doc.animations().count());
        self.add_n(Note::Cameras, doc.cameras().count());
    }

    /// One line per kind noted.
    fn lines(&self) -> Vec<String> {
        let line = |(&note, &n): (&Note, &usize)| match note {
            Note::Normals => format!(
                "normals (NORMAL) of {n} primitive(s): normals are not refinable data (limit \
                 normals replace them where a command computes them)"
            ),
            Note::Tangents => format!("tangents (TANGENT) of {n} primitive(s)"),
            Note::Colours => format!("{n} vertex colour set(s) (COLOR_n)"),
            Note::OtherTexcoords => format!(
                "{n} texture coordinate set(s) TEXCOORD_n with n > 0 (only TEXCOORD_0 is read)"
            ),
            Note::JointsWeights => format!("{n} joint or weight set(s) (JOINTS_n, WEIGHTS_n)"),
            Note::Custom => format!("custom attributes (_NAME) of {n} primitive(s) or target(s)"),
            Note::MorphTargets => {
                format!("morph targets of {n} primitive(s) (the positions without them are read)")
            }
            Note::PointsLines => {
                format!("{n} primitive(s) of points or lines (only triangles make faces)")
            }
            Note::Degenerate => {
                format!("{n} triangle(s) with two corners at one position (after welding), dropped")
            }
            Note::TexcoordsDropped => format!(
                "TEXCOORD_0: {n} primitive(s) read have none while others have, so the mesh \
                 has no texture coordinates"
            ),
            Note::Materials => format!("{n} material(s) (the faces carry no material)"),
            Note::Textures => format!("{n} texture(s)"),
            Note::Skins => {
                format!("{n} skin(s) (skinned meshes are read as they are, before skinning)")
            }
            Note::Animations => format!("{n} animation(s)"),
            Note::Cameras => format!("{n} camera(s)"),
            Note::OtherScene => format!("{n} scene(s) other than the default one"),
            Note::MeshOutsideScene => format!("{n} mesh(es) that no node of the scene places"),
        };
        self.counts.iter().map(line).collect()
    }
}

/// The welded mesh being built, instance after instance.
struct Builder {
    up: Up,
    positions: Vec<[f64; 3]>,
    /// Three per triangle.
    corners: Vec<u32>,
    /// `(s, t)` pairs, and the value of each corner (while every primitive has them).
    uv_values: Vec<f64>,
    uv_corners: Vec<u32>,
    /// Primitives read with and without `TEXCOORD_0`.
    with_uv: usize,
    without_uv: usize,
    /// Where each `(x, y, z)` (as bits) of the current instance was welded to.
    weld: HashMap<[u64; 3], u32>,
    /// The value of each `(vertex, s, t)` (as bits).
    uv_keys: HashMap<(u32, u64, u64), u32>,
}

impl Builder {
    fn new(up: Up) -> Self {
        Self {
            up,
            positions: Vec::new(),
            corners: Vec::new(),
            uv_values: Vec::new(),
            uv_corners: Vec::new(),
            with_uv: 0,
            without_uv: 0,
            weld: HashMap::new(),
            uv_keys: HashMap::new(),
        }
    }

    /// Reads the primitives of one mesh instance.
    ///
    /// # Errors
    /// [`BufferError::Bad`] naming the mesh, primitive and accessor at fault;
    /// [`BufferError::TooLarge`] when external buffers exceed the memory limit.
    fn instance(
        &mut self,
        doc: &Document,
        instance: &Instance,
        buffers: &mut Buffers<'_>,
        notes: &mut Notes,
    ) -> Result<(), BufferError> {
        self.weld.clear();
        let Some(mesh) = doc.meshes().nth(instance.mesh) else {
            return Ok(());
        };
        let m = instance.mesh;
        let place = |p: usize| match instance.node {
            Some(n) => format!("mesh {m} (node {n}), primitive {p}"),
            None => format!("mesh {m}, primitive {p}"),
        };
        for prim in mesh.primitives() {
            note_attributes(&prim, notes);
            if !triangles_mode(prim.mode()) {
                notes.add(Note::PointsLines);
                continue;
            }
            let p = prim.index();
            // The buffers of what is read: an unread attribute's missing file is no error.
            let read = [Semantic::Positions, Semantic::TexCoords(0)].map(|s| prim.get(&s));
            for accessor in read.into_iter().flatten().chain(prim.indices()) {
                if let Some(view) = accessor.view() {
                    buffers.load(&view.buffer()).map_err(|e| match e {
                        BufferError::Bad(msg) => BufferError::Bad(format!("{}: {msg}", place(p))),
                        too_large => too_large,
                    })?;
                }
            }
            self.primitive(&prim, &instance.matrix, buffers, notes)
                .map_err(|msg| BufferError::Bad(format!("{}: {msg}", place(p))))?;
        }
        Ok(())
    }

    /// Reads one triangle primitive whose buffers are loaded, placed by `matrix`.
    fn primitive(
        &mut self,
        prim: &gltf::Primitive<'_>,
        matrix: &Matrix,
        buffers: &Buffers<'_>,
        notes: &mut Notes,
    ) -> Result<(), String> {
        let accessor = prim
            .get(&Semantic::Positions)
            .ok_or("it has no POSITION attribute")?;
        let ids = self.weld_positions(&accessor, matrix, buffers)?;
        let n = ids.len();
        let uv = match prim.get(&Semantic::TexCoords(0)) {
            Some(a) => Some(texcoords(&a, buffers, n)?),
            None => None,
        };
        let order: Vec<u32> = match prim.indices() {
            Some(a) => indices(&a, buffers, n)?,
            None => (0..n as u32).collect(),
        };
        let flip = determinant3(matrix) < 0.0;
        match uv {
            Some(_) => self.with_uv += 1,
            None => self.without_uv += 1,
        }
        let keep_uv = uv.is_some() && self.without_uv == 0;
        for [a, b, c] in triangles(prim.mode(), order.len())? {
            let tri = if flip { [a, c, b] } else { [a, b, c] }.map(|k| order[k] as usize);
            let w = tri.map(|v| ids[v]);
            if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
                notes.add(Note::Degenerate);
                continue;
            }
            self.corners.extend_from_slice(&w);
            if let (Some(uv), true) = (&uv, keep_uv) {
                for (&v, &wv) in tri.iter().zip(&w) {
                    let [s, t] = uv[v];
                    let next = (self.uv_values.len() / 2) as u32;
                    let value = *self
                        .uv_keys
                        .entry((wv, s.to_bits(), t.to_bits()))
                        .or_insert(next);
                    if value == next {
                        self.uv_values.extend_from_slice(&[s, t]);
                    }
                    self.uv_corners.push(value);
                }
            }
        }
        Ok(())
    }

    /// The welded vertex of each element of the `POSITION` accessor, placed by `matrix`
    /// and turned to the up axis, new positions appended.
    fn weld_positions(
        &mut self,
        accessor: &gltf::Accessor<'_>,
        matrix: &Matrix,
        buffers: &Buffers<'_>,
    ) -> Result<Vec<u32>, String> {
        let a = accessor.index();
        let e = elements(
            accessor,
            buffers,
            "POSITION",
            Dimensions::Vec3,
            &[(DataType::F32, false)],
        )?;
        let mut ids = Vec::with_capacity(e.count);
        for i in 0..e.count {
            let p = [0, 1, 2].map(|k| e.component(i, k));
            if p.iter().any(|x| !x.is_finite()) {
                return Err(format!(
                    "POSITION accessor {a}: element {i} has a non-finite coordinate \
                     ({}, {}, {})",
                    p[0], p[1], p[2]
                ));
            }
            let q = from_gltf_frame(transform(matrix, p), self.up);
            if let Some(x) = q
                .iter()
                .find(|x| !x.is_finite() || x.abs() >= MAX_COORDINATE)
            {
                return Err(format!(
                    "POSITION accessor {a}: element {i} is placed at a coordinate of {x:e}; \
                     coordinates must be below 1e75 in magnitude"
                ));
            }
            // `+ 0.0` makes `-0.0` into `+0.0`: the same position.
            let key = q.map(|x| (x + 0.0).to_bits());
            let next = u32::try_from(self.positions.len())
                .map_err(|_| "too many vertices for 32-bit indices".to_string())?;
            let id = *self.weld.entry(key).or_insert(next);
            if id == next {
                self.positions.push(q);
            }
            ids.push(id);
        }
        Ok(ids)
    }

    /// The mesh of every triangle read, with the channel `"uv"` when every primitive read
    /// had `TEXCOORD_0`.
    fn finish(self, notes: &mut Notes) -> Result<PolyMesh, String> {
        if self.corners.is_empty() {
            let skipped = notes.lines();
            let why = match skipped.is_empty() {
                true => String::new(),
                false => format!(" (not read: {})", skipped.join("; ")),
            };
            return Err(format!(
                "no triangles to read: no mesh of the scene has a triangle primitive with a \
                 triangle of three distinct positions{why}"
            ));
        }
        let faces = self.corners.len() / 3;
        let offsets = (0..=faces)
            .map(|f| u32::try_from(3 * f))
            .collect::<Result<Vec<u32>, _>>()
            .map_err(|_| "too many triangles for 32-bit indices".to_string())?;
        let mut mesh =
            PolyMesh::new(self.positions, offsets, self.corners).map_err(|e| e.to_string())?;
        match (self.with_uv, self.without_uv) {
            (0, _) => {}
            (_, 0) => {
                let uv = FaceVarying::new("uv", 2, self.uv_values, self.uv_corners)
                    .map_err(|e| e.to_string())?;
                mesh.face_varying.push(uv);
            }
            (_, without) => notes.add_n(Note::TexcoordsDropped, without),
        }
        Ok(mesh)
    }
}

/// Notes what `prim` holds besides `POSITION` and `TEXCOORD_0`.
fn note_attributes(prim: &gltf::Primitive<'_>, notes: &mut Notes) {
    for (semantic, _) in prim.attributes() {
        match semantic {
            Semantic::Normals => notes.add(Note::Normals),
            Semantic::Tangents => notes.add(Note::Tangents),
            Semantic::Colors(_) => notes.add(Note::Colours),
            Semantic::TexCoords(k) if k > 0 => notes.add(Note::OtherTexcoords),
            Semantic::Joints(_) | Semantic::Weights(_) => notes.add(Note::JointsWeights),
            _ => {}
        }
    }
    if prim.morph_targets().next().is_some() {
        notes.add(Note::MorphTargets);
    }
}

/// The `(s, t) = (u, 1 − v)` of each element of the `TEXCOORD_0` accessor, which must
/// have `n` elements (as `POSITION`).
fn texcoords(
    accessor: &gltf::Accessor<'_>,
    buffers: &Buffers<'_>,
    n: usize,
) -> Result<Vec<[f64; 2]>, String> {
    let a = accessor.index();
    let allowed = [
        (DataType::F32, false),
        (DataType::U8, true),
        (DataType::U16, true),
    ];
    let e = elements(accessor, buffers, "TEXCOORD_0", Dimensions::Vec2, &allowed)?;
    if e.count != n {
        return Err(format!(
            "TEXCOORD_0 accessor {a}: it has {} elements, but POSITION has {n}",
            e.count
        ));
    }
    (0..n)
        .map(|i| {
            let [u, v] = [0, 1].map(|k| e.component(i, k));
            match u.is_finite() && v.is_finite() {
                true => Ok([u, 1.0 - v]),
                false => Err(format!(
                    "TEXCOORD_0 accessor {a}: element {i} is not finite ({u}, {v})"
                )),
            }
        })
        .collect()
}

/// The indices of the accessor, each checked below `n` (the vertices).
fn indices(
    accessor: &gltf::Accessor<'_>,
    buffers: &Buffers<'_>,
    n: usize,
) -> Result<Vec<u32>, String> {
    let a = accessor.index();
    let allowed = [
        (DataType::U8, false),
        (DataType::U16, false),
        (DataType::U32, false),
    ];
    let e = elements(accessor, buffers, "indices", Dimensions::Scalar, &allowed)?;
    (0..e.count)
        .map(|i| match e.index(i) {
            v if (v as usize) < n => Ok(v),
            v => Err(format!(
                "indices accessor {a}: element {i} is vertex {v}, but the primitive has {n} \
                 vertices"
            )),
        })
        .collect()
}
