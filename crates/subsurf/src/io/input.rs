//! A polygon mesh from a file or a stream of any format read (OBJ, PLY, glTF), told apart
//! by its content, read in blocks within a memory limit.
//!
//! [`read_mesh`] and [`read_mesh_from`] read their input in blocks of [`BLOCK`] bytes and
//! look at each block as it arrives:
//!
//! - the first block tells the format ([`MeshFormat`]): a file that starts with the line
//!   `ply` is PLY whatever its name; one that starts with `glTF` is binary glTF, and a
//!   JSON object named `.gltf` or holding `"asset"` in its first block is glTF (with the
//!   `gltf` feature, [`crate::io::parse_gltf`]; relative buffer URIs are looked up in the
//!   directory of the file's name); other formats with a signature (FBX, USD, ZIP, other
//!   JSON, STL and OFF text) or with a known extension (`.stl`, `.fbx`, `.usd*`, ...) are
//!   refused with a message that names the formats read; a file named `.ply` without the
//!   `ply` line is refused as not PLY, one named `.glb` or `.gltf` that is not glTF as not
//!   glTF; anything else is read as OBJ;
//! - in an OBJ file (and the body of an ASCII PLY file), each block is checked for bytes
//!   that are not text (control characters, bytes that are not UTF-8): at the first,
//!   reading stops and the file read so far is parsed, which gives the error of the whole
//!   file (the first problem, at its line), so a binary file or a stream of NUL bytes is
//!   refused after one block however long it is;
//! - a PLY header is checked as soon as it is complete;
//! - with a limit, the bytes read are counted against it (a file's size is checked before
//!   anything is read), and so, before the mesh is built, are the bytes and the lists
//!   parsed from them ([`crate::io::obj::parse_obj`] and [`parse_ply`] estimate them from
//!   counts of the file's elements).

use std::io::Read;
use std::path::Path;

use super::obj::{
    first_non_text, non_text_message, parse_obj, parse_obj_within, ObjError, ObjFile,
    PhysicalLines, Refusal,
};
use super::ply::{header_complete, parse_ply, parse_ply_within, PlyEncoding, PlyError, PlyRefusal};

/// Bytes read at a time: each block is checked as it arrives.
pub const BLOCK: usize = 1 << 20;

/// The format a mesh was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (`crate::io::obj`).
    Obj,
    /// PLY (`crate::io::ply`) in the given encoding.
    Ply(PlyEncoding),
    /// glTF 2.0 ([`crate::io::parse_gltf`]), binary (`.glb`) or JSON (`.gltf`).
    Gltf {
        /// Whether it was binary glTF.
        binary: bool,
    },
}

impl MeshFormat {
    /// The number of the first face and vertex in the file's terms: 1 in OBJ (its `f`
    /// statements count vertices from 1), 0 in PLY (its vertex lists count from 0) and in
    /// glTF (whose welded vertices and triangles the mesh numbers from 0).
    pub fn first_index(self) -> u64 {
        match self {
            Self::Obj => 1,
            Self::Ply(_) | Self::Gltf { .. } => 0,
        }
    }
}

impl std::fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Obj => f.write_str("OBJ"),
            Self::Ply(e) => write!(f, "PLY ({e})"),
            Self::Gltf { binary: true } => f.write_str("glTF (binary)"),
            Self::Gltf { binary: false } => f.write_str("glTF"),
        }
    }
}

/// A mesh read by [`read_mesh`], [`read_mesh_from`] or [`parse_mesh`].
#[derive(Clone, Debug)]
pub struct MeshFile {
    /// The format it was read from.
    pub format: MeshFormat,
    /// The mesh as an OBJ file holds it: for PLY, the mesh and, for an ASCII file, the line
    /// of each face (no tags, texture coordinates or normals); for glTF, the mesh (its
    /// texture coordinates as the channel `"uv"`).
    pub obj: ObjFile,
    /// What the file holds and the mesh leaves out, for a note (PLY's other properties and
    /// elements, [`crate::io::ply::PlyFile::ignored`]; glTF's, one line per kind).
    pub ignored: Vec<String>,
}

/// Why no mesh was read.
#[derive(Debug, thiserror::Error)]
pub enum ReadMeshError {
    /// The input could not be read.
    #[error("cannot read {name}: {error}")]
    Io {
        /// File name as given (or `<stdin>`).
        name: String,
        /// What the system said.
        error: std::io::Error,
    },
    /// The input is not valid OBJ.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The input is not valid PLY.
    #[error(transparent)]
    Ply(#[from] PlyError),
    /// The input is not glTF that can be read.
    #[cfg(feature = "gltf")]
    #[error(transparent)]
    Gltf(#[from] super::GltfError),
    /// The input is in a format that is not read.
    #[error("{name}: {message}")]
    Unsupported {
        /// File name as given.
        name: String,
        /// What the file is and which formats are read.
        message: String,
    },
    /// The input and the mesh read from it would need more memory than the limit.
    #[error(
        "{name}: reading the mesh needs {} {needed} bytes, more than the limit of {limit}",
        if *.whole { "about" } else { "at least" }
    )]
    TooLarge {
        /// File name as given.
        name: String,
        /// The bytes needed: the input's and those of the lists parsed from it (`whole`),
        /// or the input's bytes so far (a lower bound).
        needed: u64,
        /// The limit.
        limit: u64,
        /// Whether the whole input was read, so that `needed` is an estimate of everything.
        whole: bool,
    },
}

/// Reads the mesh in the file at `path` (its name as displayed in messages), refused
/// when it would need more than `limit` bytes (see the module docs).
///
/// # Errors
/// [`ReadMeshError`]: the file cannot be read, is not valid OBJ or PLY (the first problem,
/// at its line) or glTF (naming what is at fault), is in another format, or would need
/// more than `limit`.
pub fn read_mesh(path: &Path, limit: Option<u64>) -> Result<MeshFile, ReadMeshError> {
    let name = path.display().to_string();
    let io = |error| ReadMeshError::Io {
        name: name.clone(),
        error,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    let size = meta.is_file().then_some(meta.len());
    read_mesh_from(file, &name, size, limit)
}

/// Reads a mesh from `reader` (`name` in messages; its extension, if any, helps tell the
/// format), of `size` bytes when known, refused when it would need more than `limit`
/// bytes: in blocks of [`BLOCK`] bytes, each checked as it arrives (see the
/// module docs), so that a stream of anything but text stops at its first block.
///
/// # Errors
/// As [`read_mesh`]; a `size` above `limit` is refused before anything is read.
pub fn read_mesh_from<R: Read>(
    mut reader: R,
    name: &str,
    size: Option<u64>,
    limit: Option<u64>,
) -> Result<MeshFile, ReadMeshError> {
    let too_large = |needed: u64, limit: u64, whole: bool| ReadMeshError::TooLarge {
        name: name.to_owned(),
        needed,
        limit,
        whole,
    };
    let mut bytes = Vec::new();
    if let Some(size) = size {
        match limit {
            Some(limit) if size > limit => return Err(too_large(size, limit, false)),
            // The buffer for the whole file at once (and not twice its size by doubling).
            _ => bytes.reserve_exact(usize::try_from(size).unwrap_or(0)),
        }
    }
    let mut format = None;
    // Text (OBJ, an ASCII PLY body) is checked from `text_from` on, up to `checked`.
    let (mut text_from, mut checked) = (Some(0), 0);
    let mut ply_body = None;
    loop {
        let n = (&mut reader)
            .take(BLOCK as u64)
            .read_to_end(&mut bytes)
            .map_err(|error| ReadMeshError::Io {
                name: name.to_owned(),
                error,
            })?;
        let end = n < BLOCK;
        if let Some(limit) = limit.filter(|&l| bytes.len() as u64 > l) {
            return Err(too_large(bytes.len() as u64, limit, false));
        }
        let format = match format {
            Some(f) => f,
            None => {
                let f = *format.insert(sniff(&bytes, name)?);
                if f == Sniffed::Gltf {
                    // Binary, or JSON whose base64 data need no check as text.
                    text_from = None;
                }
                f
            }
        };
        if format == Sniffed::Ply && ply_body.is_none() {
            // Until the header is whole, nothing is checked as text; a binary body never.
            ply_body = header_complete(&bytes, name)?;
            text_from = match ply_body {
                Some((start, PlyEncoding::Ascii)) => Some(start),
                _ => None,
            };
            checked = text_from.unwrap_or(0);
        }
        if text_from.is_some() {
            match first_non_text(&bytes[checked..]) {
                Ok(None) => checked = bytes.len(),
                // A UTF-8 sequence cut by the block: checked with the next one.
                Err(at) => checked += at,
                // The whole file's error: the first problem, at or before this line.
                Ok(Some(at)) => {
                    let prefix = &bytes[..=checked + at];
                    return Err(match format {
                        Sniffed::Ply => not_text(ply_mesh(prefix, name, limit), prefix, name),
                        _ => not_text(obj_mesh(prefix, name, limit), prefix, name),
                    });
                }
            }
        }
        if end {
            break;
        }
    }
    match format {
        Some(Sniffed::Ply) => ply_mesh(&bytes, name, limit),
        Some(Sniffed::Gltf) => gltf_mesh(&bytes, name, limit),
        _ => obj_mesh(&bytes, name, limit),
    }
}

/// Reads a mesh from `bytes` by their content, as [`read_mesh_from`] does (without a
/// memory limit).
///
/// # Errors
/// As [`read_mesh`].
pub fn parse_mesh(bytes: &[u8], name: &str) -> Result<MeshFile, ReadMeshError> {
    match sniff(bytes, name)? {
        Sniffed::Ply => ply_mesh(bytes, name, None),
        Sniffed::Obj => obj_mesh(bytes, name, None),
        Sniffed::Gltf => gltf_mesh(bytes, name, None),
    }
}

/// The readers, by content.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Sniffed {
    Obj,
    Ply,
    /// Binary or JSON glTF (only with the `gltf` feature).
    Gltf,
}

/// Formats recognised by the start of the file, and not read.
const SIGNATURES: [(&[u8], &str); 4] = [
    (b"Kaydara FBX Binary", "an FBX file"),
    (b"PXR-USDC", "a USD file"),
    (b"#usda", "a USD file"),
    (b"PK\x03\x04", "a ZIP archive (.usdz, .3mf, ...)"),
];

/// Formats recognised by the extension of the name, and not read.
const EXTENSIONS: [(&str, &str); 17] = [
    ("stl", "an STL file"),
    ("fbx", "an FBX file"),
    ("usd", "a USD file"),
    ("usda", "a USD file"),
    ("usdc", "a USD file"),
    ("usdz", "a USD file"),
    ("dae", "a COLLADA file"),
    ("3ds", "a 3DS file"),
    ("blend", "a Blender file"),
    ("abc", "an Alembic file"),
    ("off", "an OFF file"),
    ("3mf", "a 3MF file"),
    ("x3d", "an X3D file"),
    ("wrl", "a VRML file"),
    ("step", "a STEP file"),
    ("stp", "a STEP file"),
    ("igs", "an IGES file"),
];

/// The formats read, for messages.
#[cfg(feature = "gltf")]
const FORMATS_READ: &str = "OBJ, PLY and glTF (.gltf, .glb) files only";
#[cfg(not(feature = "gltf"))]
const FORMATS_READ: &str = "OBJ and PLY files only (glTF input needs the `gltf` feature of \
                            the subsurf library)";

/// The reader for a file that starts with `start` and is called `name`, or the error
/// for a file in another format.
fn sniff(start: &[u8], name: &str) -> Result<Sniffed, ReadMeshError> {
    if start.starts_with(b"ply\n") || start.starts_with(b"ply\r\n") {
        return Ok(Sniffed::Ply);
    }
    let unsupported = |what: &str| ReadMeshError::Unsupported {
        name: name.to_owned(),
        message: format!(
            "this looks like {what}; meshes are read from {FORMATS_READ} (PLY: ascii, \
             binary_little_endian or binary_big_endian); convert it to one of them"
        ),
    };
    let ext = Path::new(name)
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let text = start.trim_ascii_start();
    if let Some(gltf) = sniff_gltf(start, text, ext.as_deref()) {
        return match gltf {
            Ok(_) if cfg!(feature = "gltf") => Ok(Sniffed::Gltf),
            Ok(what) => Err(unsupported(what)),
            Err(message) => Err(ReadMeshError::Unsupported {
                name: name.to_owned(),
                message,
            }),
        };
    }
    if let Some((_, what)) = SIGNATURES.iter().find(|(s, _)| start.starts_with(s)) {
        return Err(unsupported(what));
    }
    let first_word = text
        .split(|b| b.is_ascii_whitespace())
        .next()
        .unwrap_or_default();
    match first_word {
        _ if text.starts_with(b"{") => return Err(unsupported("a JSON file (not glTF)")),
        b"solid" => return Err(unsupported("an STL file")),
        b"OFF" | b"COFF" | b"NOFF" => return Err(unsupported("an OFF file")),
        _ => {}
    }
    match ext.as_deref() {
        Some("ply") => Err(PlyError {
            source_name: name.to_owned(),
            line: Some(1),
            message: "not a PLY file: the first line is not 'ply'".into(),
        }
        .into()),
        Some(ext) => match EXTENSIONS.iter().find(|(e, _)| *e == ext) {
            Some((_, what)) => Err(unsupported(what)),
            None => Ok(Sniffed::Obj),
        },
        None => Ok(Sniffed::Obj),
    }
}

/// Whether a file that starts with `start` (`text` without leading whitespace), of
/// extension `ext`, is glTF: `Some(Ok(what it is))` for binary glTF (`glTF`) and for a
/// JSON object named `.gltf` or holding `"asset"`; `Some(Err(message))` for a file named
/// `.glb` or `.gltf` that is not; `None` for anything else.
fn sniff_gltf(
    start: &[u8],
    text: &[u8],
    ext: Option<&str>,
) -> Option<Result<&'static str, String>> {
    let json = text.starts_with(b"{");
    let asset = json && start.windows(7).any(|w| w == b"\"asset\"");
    match ext {
        _ if start.starts_with(b"glTF") => Some(Ok("a binary glTF (.glb) file")),
        _ if json && (asset || ext == Some("gltf")) => Some(Ok("a glTF (.gltf) file")),
        Some("glb") => Some(Err(
            "not a binary glTF file: it does not start with 'glTF'".into()
        )),
        Some("gltf") => Some(Err(
            "not a glTF file: it is not a JSON object (it does not start with '{')".into(),
        )),
        _ => None,
    }
}

/// The error of a text input whose last byte in `prefix` is its first that is not text:
/// `read`, the reading of `prefix`, which gives the error of the whole file (the first
/// problem, at or before the line of that byte, which the readers refuse).
fn not_text(read: Result<MeshFile, ReadMeshError>, prefix: &[u8], name: &str) -> ReadMeshError {
    match read {
        Err(e) => e,
        // Not reached: the prefix's last line is not text, which the readers refuse.
        Ok(_) => {
            let mut lines = PhysicalLines {
                rest: prefix,
                line: 0,
            };
            let mut last = (1, prefix);
            while let Some(line) = lines.next() {
                last = line;
            }
            ObjError {
                source_name: name.to_owned(),
                line: Some(last.0),
                message: non_text_message(last.1, last.0),
            }
            .into()
        }
    }
}

fn obj_mesh(bytes: &[u8], name: &str, limit: Option<u64>) -> Result<MeshFile, ReadMeshError> {
    let obj = match limit {
        None => parse_obj(bytes, name)?,
        Some(limit) => parse_obj_within(bytes, name, limit).map_err(|r| match r {
            Refusal::Obj(e) => e.into(),
            Refusal::TooLarge { needed } => ReadMeshError::TooLarge {
                name: name.to_owned(),
                needed,
                limit,
                whole: true,
            },
        })?,
    };
    let mut ignored = Vec::new();
    if !obj.normals.is_empty() {
        ignored.push(format!(
            "{} normals (vn): normals are not refinable data (limit normals replace them \
             where a command computes them, e.g. subdivide --limit)",
            obj.normals.len()
        ));
    }
    if obj.smoothing_groups > 0 {
        ignored.push(format!(
            "{} smoothing-group statement(s) (s): a subdivision surface is smooth everywhere \
             but at its creases, so they are not kept (use t crease tags for sharp edges)",
            obj.smoothing_groups
        ));
    }
    Ok(MeshFile {
        format: MeshFormat::Obj,
        obj,
        ignored,
    })
}

fn ply_mesh(bytes: &[u8], name: &str, limit: Option<u64>) -> Result<MeshFile, ReadMeshError> {
    let ply = match limit {
        None => parse_ply(bytes, name)?,
        Some(limit) => parse_ply_within(bytes, name, limit).map_err(|r| match r {
            PlyRefusal::Ply(e) => e.into(),
            PlyRefusal::TooLarge { needed } => ReadMeshError::TooLarge {
                name: name.to_owned(),
                needed,
                limit,
                whole: true,
            },
        })?,
    };
    Ok(MeshFile {
        format: MeshFormat::Ply(ply.encoding),
        obj: ObjFile {
            mesh: ply.mesh,
            face_lines: ply.face_lines,
            ..ObjFile::default()
        },
        ignored: ply.ignored,
    })
}

#[cfg(feature = "gltf")]
fn gltf_mesh(bytes: &[u8], name: &str, limit: Option<u64>) -> Result<MeshFile, ReadMeshError> {
    use super::gltf_read::{parse_gltf_within, Refusal};
    let dir = Path::new(name).parent();
    let file = parse_gltf_within(bytes, name, dir, super::Up::Z, limit).map_err(|r| match r {
        Refusal::Gltf(e) => ReadMeshError::Gltf(e),
        Refusal::TooLarge { needed } => ReadMeshError::TooLarge {
            name: name.to_owned(),
            needed,
            limit: limit.unwrap_or(0),
            whole: true,
        },
    })?;
    Ok(MeshFile {
        format: MeshFormat::Gltf {
            binary: file.binary,
        },
        obj: ObjFile {
            mesh: file.mesh,
            ..ObjFile::default()
        },
        ignored: file.ignored,
    })
}

/// Not reached: without the `gltf` feature, [`sniff`] refuses glTF.
#[cfg(not(feature = "gltf"))]
fn gltf_mesh(_: &[u8], name: &str, _: Option<u64>) -> Result<MeshFile, ReadMeshError> {
    Err(ReadMeshError::Unsupported {
        name: name.to_owned(),
        message: format!("glTF is not read; meshes are read from {FORMATS_READ}"),
    })
}
