//! The PLY reader: the header ([`parse_header`]), then the elements in the order the header
//! lists them, from text ([`Ascii`]) or binary records ([`Binary`]) through one loop
//! ([`read_elements`]), with the checks that need the whole file (vertex indices of faces
//! listed before the vertices) at the end.

use std::str::SplitAsciiWhitespace;

use crate::io::obj::{first_non_text, non_text_message, PhysicalLines};
use crate::mesh::{PolyMesh, MAX_COORDINATE};

/// The three encodings of a PLY body (the header's `format` line).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlyEncoding {
    /// `format ascii 1.0`: one record per line, values as decimal text.
    Ascii,
    /// `format binary_little_endian 1.0`.
    BinaryLittleEndian,
    /// `format binary_big_endian 1.0`.
    BinaryBigEndian,
}

impl std::fmt::Display for PlyEncoding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Ascii => "ascii",
            Self::BinaryLittleEndian => "binary_little_endian",
            Self::BinaryBigEndian => "binary_big_endian",
        })
    }
}

/// A polygon mesh read by [`parse_ply`].
#[derive(Clone, Debug, PartialEq)]
pub struct PlyFile {
    /// The mesh: the `vertex` element's `x y z`, the `face` element's vertex lists
    /// (0-based, as PLY writes them).
    pub mesh: PolyMesh,
    /// The body's encoding.
    pub encoding: PlyEncoding,
    /// The 1-based line of each face's record in an ASCII file; empty for a binary one.
    pub face_lines: Vec<u32>,
    /// What the file holds and the mesh leaves out, for a note: other properties of the
    /// vertices and faces (`vertex properties nx, ny, nz`) and other elements with records
    /// (`element 'edge' (12 records)`).
    pub ignored: Vec<String>,
}

/// An error reading PLY: file, line (of the header, or of an ASCII body) and what is
/// wrong. Errors in a binary body name the element and record instead of a line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{source_name}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
pub struct PlyError {
    /// File name as given (or `<stdin>`).
    pub source_name: String,
    /// 1-based line, when the error belongs to one.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
}

/// The longest header read: real headers have a few hundred bytes, so a file without
/// `end_header` in its first MiB is not PLY, however long it is.
pub const MAX_HEADER: usize = 1 << 20;

/// Reads a PLY file (ASCII, binary little- or big-endian) as a polygon mesh.
///
/// Reads the `vertex` element's `x`, `y`, `z` (of any numeric type; `float` values are
/// single precision, as the file stores them) and the `face` element's `vertex_indices`
/// (or `vertex_index`) list, with any count and integer index types. Other properties and
/// elements are read past (lists included) and listed in [`PlyFile::ignored`]; elements
/// may come in any order. Follows the format as Greg Turk describes it ("The PLY Polygon
/// File Format", 1994): a header of text lines (`ply`, `format`, `comment`, `obj_info`,
/// `element`, `property`, `end_header`), then each element's records in the header's
/// order. An ASCII body has one record per line (blank lines are skipped; lines end with
/// `\n`, `\r\n` or `\r`).
///
/// # Errors
/// A [`PlyError`] naming `source_name` and the line (header lines, ASCII records) or the
/// element and record (binary records, 0-based as PLY indices are): a malformed header
/// (no `ply` line, an unknown keyword, type or format, a property outside an element, a
/// repeated property, a list of non-integer counts or indices, no `vertex` element or no
/// `x y z`, a `face` element without a vertex list, records without properties); a
/// malformed, non-finite or out-of-range value (integers in their type's range,
/// coordinates below [`MAX_COORDINATE`] in magnitude); a face of fewer than 3 or more than
/// 65 535 vertices; a negative or out-of-range vertex index (checked once every element is
/// read); a file that ends before the header's records do, or data after them.
pub fn parse_ply(bytes: &[u8], source_name: &str) -> Result<PlyFile, PlyError> {
    parse_ply_in(bytes, source_name, None).map_err(|r| match r {
        PlyRefusal::Ply(e) => e,
        PlyRefusal::TooLarge { .. } => unreachable!("no memory limit was given"),
    })
}

/// Why [`parse_ply_within`] gave no file.
#[derive(Debug)]
pub(crate) enum PlyRefusal {
    /// The file is not valid PLY.
    Ply(PlyError),
    /// Holding the file and the mesh read from it would take about `needed` bytes.
    TooLarge { needed: u64 },
}

/// [`parse_ply`], refused after the header when the bytes and the lists the header calls
/// for (as many as the bytes can hold) would need more than `limit` bytes.
pub(crate) fn parse_ply_within(
    bytes: &[u8],
    source_name: &str,
    limit: u64,
) -> Result<PlyFile, PlyRefusal> {
    parse_ply_in(bytes, source_name, Some(limit))
}

/// Whether `prefix`, the start of a PLY file, holds its whole header: where the body
/// starts and its encoding when it does (and the header is valid), `None` when more bytes
/// are needed, the header's error otherwise (also when [`MAX_HEADER`] bytes hold no
/// `end_header`).
pub(crate) fn header_complete(
    prefix: &[u8],
    source_name: &str,
) -> Result<Option<(usize, PlyEncoding)>, PlyError> {
    match parse_header(prefix) {
        Ok(h) => Ok(Some((h.end, h.encoding))),
        Err(HeaderError::Incomplete) if prefix.len() < MAX_HEADER => Ok(None),
        Err(e) => Err(e.into_error(source_name)),
    }
}

/// The mesh data read from a file, before it becomes a [`PolyMesh`].
pub(super) struct PlyData {
    pub(super) positions: Vec<[f64; 3]>,
    /// `nx ny nz` of the vertices, when the file has all three (scalars).
    pub(super) normals: Option<Vec<[f64; 3]>>,
    pub(super) face_offsets: Vec<u32>,
    pub(super) face_verts: Vec<u32>,
    pub(super) face_lines: Vec<u32>,
    pub(super) encoding: PlyEncoding,
    pub(super) ignored: Vec<String>,
}

fn parse_ply_in(
    bytes: &[u8],
    source_name: &str,
    limit: Option<u64>,
) -> Result<PlyFile, PlyRefusal> {
    let data = read_data(bytes, source_name, limit)?;
    let ply = |line: Option<usize>, message: String| {
        PlyRefusal::Ply(PlyError {
            source_name: source_name.to_owned(),
            line,
            message,
        })
    };
    // Faces, indices and coordinates were checked as they were read.
    let mesh = PolyMesh::new(data.positions, data.face_offsets, data.face_verts)
        .map_err(|e| ply(None, e.to_string()))?;
    Ok(PlyFile {
        mesh,
        encoding: data.encoding,
        face_lines: data.face_lines,
        ignored: data.ignored,
    })
}

/// Reads the header and the elements of `bytes` (refused as [`parse_ply_within`] says
/// when a `limit` is given).
pub(super) fn read_data(
    bytes: &[u8],
    source_name: &str,
    limit: Option<u64>,
) -> Result<PlyData, PlyRefusal> {
    let header = parse_header(bytes).map_err(|e| PlyRefusal::Ply(e.into_error(source_name)))?;
    let body = &bytes[header.end..];
    let roles = Roles::new(&header).map_err(|(line, message)| {
        PlyRefusal::Ply(PlyError {
            source_name: source_name.to_owned(),
            line: Some(line),
            message,
        })
    })?;
    if let Some(limit) = limit {
        let needed = memory(&header, &roles, bytes.len());
        if needed > limit {
            return Err(PlyRefusal::TooLarge { needed });
        }
    }
    let read = match header.encoding {
        PlyEncoding::Ascii => {
            let mut ascii = Ascii {
                lines: PhysicalLines {
                    rest: body,
                    line: header.lines,
                },
                line: header.lines,
                tokens: "".split_ascii_whitespace(),
            };
            read_elements(&header, &roles, &mut ascii, body.len())
        }
        encoding => {
            let big = encoding == PlyEncoding::BinaryBigEndian;
            let mut binary = Binary { body, at: 0, big };
            read_elements(&header, &roles, &mut binary, body.len())
        }
    };
    read.map_err(|(line, message)| {
        PlyRefusal::Ply(PlyError {
            source_name: source_name.to_owned(),
            line,
            message,
        })
    })
}

/// Scalar types of PLY.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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

    fn name(self) -> &'static str {
        match self {
            Self::I8 => "char",
            Self::U8 => "uchar",
            Self::I16 => "short",
            Self::U16 => "ushort",
            Self::I32 => "int",
            Self::U32 => "uint",
            Self::F32 => "float",
            Self::F64 => "double",
        }
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }

    /// The range of an integer type.
    fn range(self) -> (i64, i64) {
        match self {
            Self::I8 => (i8::MIN.into(), i8::MAX.into()),
            Self::U8 => (0, u8::MAX.into()),
            Self::I16 => (i16::MIN.into(), i16::MAX.into()),
            Self::U16 => (0, u16::MAX.into()),
            Self::I32 => (i32::MIN.into(), i32::MAX.into()),
            _ => (0, u32::MAX.into()),
        }
    }

    /// The value of the `size()` bytes `b`, as `f64` (exact for every PLY type).
    fn decode(self, b: &[u8], big: bool) -> f64 {
        let mut x = [0u8; 8];
        let n = self.size();
        x[..n].copy_from_slice(&b[..n]);
        if big {
            x[..n].reverse();
        }
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

    /// The value of the decimal `tok`: an integer in the type's range, or a number
    /// (`float`: rounded to single precision, as the type holds it).
    fn parse_text(self, tok: &str) -> Result<f64, String> {
        match self {
            Self::F32 => tok.parse::<f32>().map(f64::from),
            Self::F64 => tok.parse::<f64>(),
            _ => {
                let (lo, hi) = self.range();
                return match tok.parse::<i64>() {
                    Ok(i) if (lo..=hi).contains(&i) => Ok(i as f64),
                    Ok(_) => Err(format!("{tok} is out of the range of {}", self.name())),
                    Err(_) => Err(format!("'{tok}' is not an integer ({})", self.name())),
                };
            }
        }
        .map_err(|_| format!("'{tok}' is not a number"))
    }
}

/// A property: a scalar, or a list with a count type and an item type.
#[derive(Clone, Debug)]
struct Property {
    name: String,
    ty: Scalar,
    list: Option<Scalar>,
}

/// An element of the header, with the line that declares it.
#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
    line: usize,
}

/// A parsed header: the encoding, the elements, where the body starts and how many lines
/// the header has.
struct Header {
    encoding: PlyEncoding,
    elements: Vec<Element>,
    end: usize,
    lines: usize,
}

/// Why a header was not read: its bytes end before `end_header`, or a line is wrong.
enum HeaderError {
    Incomplete,
    Line(usize, String),
    File(String),
}

impl HeaderError {
    fn into_error(self, source_name: &str) -> PlyError {
        let (line, message) = match self {
            Self::Incomplete => (None, "the PLY header has no end_header line".to_owned()),
            Self::Line(line, message) => (Some(line), message),
            Self::File(message) => (None, message),
        };
        PlyError {
            source_name: source_name.to_owned(),
            line,
            message,
        }
    }
}

/// Reads the header at the start of `bytes` (its lines end with `\n` or `\r\n`).
fn parse_header(bytes: &[u8]) -> Result<Header, HeaderError> {
    let mut at = 0;
    let mut no = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if at >= MAX_HEADER {
            return Err(HeaderError::File(format!(
                "the PLY header has no end_header line in its first {} KiB",
                MAX_HEADER >> 10
            )));
        }
        let Some(nl) = bytes[at..].iter().position(|&b| b == b'\n') else {
            return Err(HeaderError::Incomplete);
        };
        let raw = &bytes[at..at + nl];
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        at += nl + 1;
        no += 1;
        let bad = |m: String| HeaderError::Line(no, m);
        if matches!(first_non_text(raw), Ok(Some(_)) | Err(_)) {
            return Err(bad(non_text_message(raw, no)));
        }
        let line = std::str::from_utf8(raw).unwrap_or_default();
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        if no == 1 {
            if words != ["ply"] {
                return Err(bad("not a PLY file: the first line is not 'ply'".into()));
            }
            continue;
        }
        match words.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("end_header") => break,
            Some("format") => {
                let e = parse_format(&words, line).map_err(bad)?;
                if encoding.replace(e).is_some() {
                    return Err(bad("a second format line".into()));
                }
            }
            Some("element") => {
                let el = parse_element(&words, line, no).map_err(bad)?;
                if elements.iter().any(|e| e.name == el.name) {
                    return Err(bad(format!("a second element '{}'", el.name)));
                }
                elements.push(el);
            }
            Some("property") => add_property(&mut elements, &words, line).map_err(bad)?,
            Some(other) => {
                return Err(bad(format!(
                    "unknown PLY header keyword '{other}' (a header ends with the line \
                     end_header)"
                )));
            }
        }
    }
    let encoding =
        encoding.ok_or_else(|| HeaderError::File("the PLY header has no format line".into()))?;
    Ok(Header {
        encoding,
        elements,
        end: at,
        lines: no,
    })
}

/// The encoding of a `format ENCODING 1.0` line (`words`, from `line`).
fn parse_format(words: &[&str], line: &str) -> Result<PlyEncoding, String> {
    let e = match words.get(1).copied() {
        Some("ascii") => PlyEncoding::Ascii,
        Some("binary_little_endian") => PlyEncoding::BinaryLittleEndian,
        Some("binary_big_endian") => PlyEncoding::BinaryBigEndian,
        _ => {
            return Err(format!(
                "unknown PLY format '{}' (expected ascii, binary_little_endian or \
                 binary_big_endian)",
                words[1..].join(" ")
            ))
        }
    };
    if words.len() != 3 || !matches!(words[2], "1.0" | "1") {
        return Err(format!(
            "PLY format line '{line}': only version 1.0 is read"
        ));
    }
    Ok(e)
}

/// The element of an `element NAME COUNT` line (`words`, from `line`, header line `no`),
/// without properties yet.
fn parse_element(words: &[&str], line: &str, no: usize) -> Result<Element, String> {
    let [_, name, count] = words[..] else {
        return Err(format!(
            "malformed element line '{line}' (expected 'element NAME COUNT')"
        ));
    };
    let count = count
        .parse()
        .map_err(|_| format!("element {name}: '{count}' is not a count (an integer ≥ 0)"))?;
    Ok(Element {
        name: name.to_owned(),
        count,
        props: Vec::new(),
        line: no,
    })
}

/// Adds the property of a `property` line (`words`, from `line`) to the last of
/// `elements`, which must not list it yet.
fn add_property(elements: &mut [Element], words: &[&str], line: &str) -> Result<(), String> {
    let prop = parse_property(words, line)?;
    let Some(el) = elements.last_mut() else {
        return Err("a property before any element".into());
    };
    if el.props.iter().any(|p| p.name == prop.name) {
        return Err(format!(
            "element {} lists property '{}' twice",
            el.name, prop.name
        ));
    }
    el.props.push(prop);
    Ok(())
}

/// `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`.
fn parse_property(words: &[&str], line: &str) -> Result<Property, String> {
    let ty = |s: &str| {
        Scalar::parse(s).ok_or_else(|| {
            format!(
                "unknown PLY type '{s}' (expected char, uchar, short, ushort, int, uint, float \
                 or double, or int8 ... float64)"
            )
        })
    };
    match *words {
        [_, "list", count, item, name] => {
            let count = ty(count)?;
            if !count.is_integer() {
                return Err(format!(
                    "list {name}: its count type {} is not an integer type",
                    count.name()
                ));
            }
            Ok(Property {
                name: name.to_owned(),
                ty: ty(item)?,
                list: Some(count),
            })
        }
        [_, t, name] if t != "list" => Ok(Property {
            name: name.to_owned(),
            ty: ty(t)?,
            list: None,
        }),
        _ => Err(format!(
            "malformed property line '{line}' (expected 'property TYPE NAME' or 'property list \
             COUNT_TYPE ITEM_TYPE NAME')"
        )),
    }
}

/// What each element and property is read for: the vertices' coordinates (and normals),
/// the faces' vertex list; everything else is read past.
struct Roles {
    /// The `vertex` element, its `x y z` and, when all three are scalars, `nx ny nz`.
    vertex: (usize, [usize; 3], Option<[usize; 3]>),
    /// The `face` element and its vertex list.
    face: Option<(usize, usize)>,
    /// What is not read, for [`PlyFile::ignored`].
    ignored: Vec<String>,
}

impl Roles {
    /// The roles of `header`'s elements, or the line and message of what is missing.
    fn new(header: &Header) -> Result<Roles, (usize, String)> {
        let els = &header.elements;
        if let Some(e) = els.iter().find(|e| e.props.is_empty() && e.count > 0) {
            return Err((
                e.line,
                format!(
                    "element {} has {} records but no properties",
                    e.name, e.count
                ),
            ));
        }
        let Some(v) = els.iter().position(|e| e.name == "vertex") else {
            return Err((
                header.lines,
                "the PLY header has no vertex element, so the file holds no mesh".into(),
            ));
        };
        let scalar = |name: &str| -> Result<Option<usize>, (usize, String)> {
            match els[v].props.iter().position(|p| p.name == name) {
                Some(i) if els[v].props[i].list.is_some() => Err((
                    els[v].line,
                    format!("property {name} of element vertex is a list, not a number"),
                )),
                found => Ok(found),
            }
        };
        let mut xyz = [0; 3];
        for (k, c) in ["x", "y", "z"].into_iter().enumerate() {
            xyz[k] = scalar(c)?.ok_or_else(|| {
                (
                    els[v].line,
                    format!("element vertex has no property {c} (x, y and z are needed)"),
                )
            })?;
        }
        let normal = |c: &str| {
            let props = &els[v].props;
            props.iter().position(|p| p.name == c && p.list.is_none())
        };
        let normals = match [normal("nx"), normal("ny"), normal("nz")] {
            [Some(a), Some(b), Some(c)] => Some([a, b, c]),
            _ => None,
        };
        let face = match els.iter().position(|e| e.name == "face") {
            None => None,
            Some(f) => {
                let props = &els[f].props;
                let list = ["vertex_indices", "vertex_index"]
                    .iter()
                    .find_map(|n| props.iter().position(|p| p.name == *n && p.list.is_some()))
                    .ok_or_else(|| {
                        (
                            els[f].line,
                            "element face has no vertex_indices (or vertex_index) list".to_owned(),
                        )
                    })?;
                if !props[list].ty.is_integer() {
                    return Err((
                        els[f].line,
                        format!(
                            "list {} of element face holds {} values, not integer indices",
                            props[list].name,
                            props[list].ty.name()
                        ),
                    ));
                }
                Some((f, list))
            }
        };
        let mut ignored = Vec::new();
        for (i, e) in els.iter().enumerate() {
            let used: &[usize] = match (i == v, face) {
                (true, _) => &xyz,
                (false, Some((f, list))) if f == i => &[list],
                _ => {
                    if e.count > 0 {
                        let s = if e.count == 1 { "" } else { "s" };
                        ignored.push(format!("element {} ({} record{s})", e.name, e.count));
                    }
                    continue;
                }
            };
            let rest: Vec<&str> = (e.props.iter().enumerate())
                .filter(|(k, _)| !used.contains(k))
                .map(|(_, p)| p.name.as_str())
                .collect();
            if !rest.is_empty() && e.count > 0 {
                let s = if rest.len() == 1 { "y" } else { "ies" };
                ignored.push(format!("{} propert{s} {}", e.name, rest.join(", ")));
            }
        }
        Ok(Roles {
            vertex: (v, xyz, normals),
            face,
            ignored,
        })
    }
}

/// An upper bound of the peak memory of reading a file of `len` bytes with `header`: the
/// bytes, 24 bytes per vertex (48 with normals), 8 per face (offset and line), and twice
/// 4 per face corner (a list that grows by doubling), as many as the body can hold (a
/// binary vertex needs its record's bytes, a face corner the size of its index type; an
/// ASCII value at least two bytes).
fn memory(header: &Header, roles: &Roles, len: usize) -> u64 {
    let body = len.saturating_sub(header.end) as u64;
    let binary = header.encoding != PlyEncoding::Ascii;
    let min_size = |e: &Element| -> u64 {
        let fixed: usize = e.props.iter().map(|p| p.list.unwrap_or(p.ty).size()).sum();
        if binary {
            fixed.max(1) as u64
        } else {
            2 * e.props.len().max(1) as u64
        }
    };
    let (v, _, normals) = roles.vertex;
    let vertex = &header.elements[v];
    let per_vertex = if normals.is_some() { 48 } else { 24 };
    let vertices = vertex.count.min(body / min_size(vertex));
    let (faces, corners) = match roles.face {
        Some((f, list)) => {
            let e = &header.elements[f];
            let item = if binary { e.props[list].ty.size() } else { 2 } as u64;
            (e.count.min(body / min_size(e)), body / item)
        }
        None => (0, 0),
    };
    (len as u64)
        .saturating_add(vertices.saturating_mul(per_vertex))
        .saturating_add(faces.saturating_mul(8))
        .saturating_add(corners.saturating_mul(8))
}

/// Why a [`Body`] gave no value: the file ended, or the value is wrong (a message).
enum Stop {
    End,
    Bad(String),
}

impl From<String> for Stop {
    fn from(message: String) -> Self {
        Self::Bad(message)
    }
}

/// Where values come from: the lines of an ASCII body or the bytes of a binary one.
/// [`read_elements`] adds the element and record to the messages.
trait Body {
    /// Starts the next record.
    fn start(&mut self) -> Result<(), Stop>;
    /// The next value, of type `ty`.
    fn value(&mut self, ty: Scalar) -> Result<f64, Stop>;
    /// Ends a record.
    fn end(&mut self) -> Result<(), Stop>;
    /// The line of the record being read (ASCII).
    fn line(&self) -> Option<usize>;
    /// Checks that nothing follows the last record: the line and message of what does.
    fn finish(&mut self) -> Result<(), (Option<usize>, String)>;
    /// Reads past `n` values of type `ty`.
    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Stop> {
        for _ in 0..n {
            self.value(ty)?;
        }
        Ok(())
    }
}

/// An ASCII body: a record per line, values separated by whitespace.
struct Ascii<'a> {
    lines: PhysicalLines<'a>,
    line: usize,
    tokens: SplitAsciiWhitespace<'a>,
}

impl<'a> Ascii<'a> {
    /// The next line that is not blank, with its number.
    fn next_line(&mut self) -> Result<Option<(usize, &'a str)>, (usize, String)> {
        while let Some((no, raw)) = self.lines.next() {
            let text = match std::str::from_utf8(raw) {
                Ok(t) if first_non_text(raw) == Ok(None) => t,
                _ => return Err((no, non_text_message(raw, no))),
            };
            if !text.trim_ascii().is_empty() {
                return Ok(Some((no, text)));
            }
        }
        Ok(None)
    }
}

impl Body for Ascii<'_> {
    fn start(&mut self) -> Result<(), Stop> {
        match self.next_line() {
            Ok(Some((no, text))) => {
                self.line = no;
                self.tokens = text.split_ascii_whitespace();
                Ok(())
            }
            Ok(None) => Err(Stop::End),
            Err((no, message)) => {
                self.line = no;
                Err(Stop::Bad(message))
            }
        }
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, Stop> {
        match self.tokens.next() {
            Some(tok) => Ok(ty.parse_text(tok)?),
            None => Err(Stop::Bad(
                "the line has fewer values than the element's properties".into(),
            )),
        }
    }

    fn end(&mut self) -> Result<(), Stop> {
        match self.tokens.next() {
            None => Ok(()),
            Some(tok) => Err(Stop::Bad(format!(
                "the line has more values than the element's properties (from '{tok}' on)"
            ))),
        }
    }

    fn line(&self) -> Option<usize> {
        Some(self.line)
    }

    fn finish(&mut self) -> Result<(), (Option<usize>, String)> {
        match self.next_line() {
            Ok(None) => Ok(()),
            Ok(Some((no, _))) => Err((
                Some(no),
                "data after the last record of the last element (the header lists fewer \
                 records than the file has)"
                    .into(),
            )),
            Err((no, message)) => Err((Some(no), message)),
        }
    }
}

/// A binary body.
struct Binary<'a> {
    body: &'a [u8],
    at: usize,
    big: bool,
}

impl Binary<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], Stop> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.body.len());
        let end = end.ok_or(Stop::End)?;
        let b = &self.body[self.at..end];
        self.at = end;
        Ok(b)
    }
}

impl Body for Binary<'_> {
    fn start(&mut self) -> Result<(), Stop> {
        Ok(())
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, Stop> {
        let big = self.big;
        Ok(ty.decode(self.take(ty.size())?, big))
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> Result<(), Stop> {
        let bytes = n.saturating_mul(ty.size());
        self.take(bytes).map(|_| ())
    }

    fn end(&mut self) -> Result<(), Stop> {
        Ok(())
    }

    fn line(&self) -> Option<usize> {
        None
    }

    fn finish(&mut self) -> Result<(), (Option<usize>, String)> {
        match self.body.len() - self.at {
            0 => Ok(()),
            n => Err((
                None,
                format!(
                    "{n} bytes after the last record of the last element (the header lists \
                     fewer records than the file has)"
                ),
            )),
        }
    }
}

/// The mesh data of `header`'s elements from `body` (of `len` bytes, for capacities).
fn read_elements<B: Body>(
    header: &Header,
    roles: &Roles,
    body: &mut B,
    len: usize,
) -> Result<PlyData, (Option<usize>, String)> {
    let (v, xyz, normal_props) = roles.vertex;
    let nv = header.elements[v].count;
    // Capacities for what the body can hold at most (at least a byte per record), never
    // for counts alone.
    let cap = |count: u64| count.min(len as u64) as usize;
    let mut data = PlyData {
        positions: Vec::with_capacity(cap(nv)),
        normals: normal_props.map(|_| Vec::with_capacity(cap(nv))),
        face_offsets: vec![0],
        face_verts: Vec::new(),
        face_lines: Vec::new(),
        encoding: header.encoding,
        ignored: roles.ignored.clone(),
    };
    let mut values = Vec::new();
    for (i, el) in header.elements.iter().enumerate() {
        let faces = roles.face.filter(|&(f, _)| f == i).map(|(_, list)| list);
        if faces.is_some() {
            data.face_offsets.reserve(cap(el.count));
        }
        values.clear();
        values.resize(el.props.len(), 0.0);
        for r in 0..el.count {
            // The element and record (0-based, as PLY's indices) in front of a message; at
            // the end of the file, how many records were read.
            let at = |body: &B, stop: Stop| match stop {
                Stop::Bad(m) => (body.line(), format!("{} {r}: {m}", el.name)),
                Stop::End => (
                    None,
                    format!(
                        "the file ends in element {} after {r} of its {} records (is it \
                         truncated?)",
                        el.name, el.count
                    ),
                ),
            };
            let bad = |body: &B, m: String| at(body, Stop::Bad(m));
            body.start().map_err(|e| at(body, e))?;
            for (k, p) in el.props.iter().enumerate() {
                let Some(count_ty) = p.list else {
                    values[k] = body.value(p.ty).map_err(|e| at(body, named(p, e)))?;
                    continue;
                };
                let n = body.value(count_ty).map_err(|e| at(body, named(p, e)))?;
                if n < 0.0 {
                    return Err(bad(body, format!("list {} has the count {n}", p.name)));
                }
                let n = n as usize;
                match faces == Some(k) {
                    true => read_face(body, p, n, nv, &mut data),
                    false => body.skip(p.ty, n).map_err(|e| named(p, e)),
                }
                .map_err(|e| at(body, e))?;
            }
            body.end().map_err(|e| at(body, e))?;
            if i == v {
                let p = xyz.map(|k| values[k]);
                check_coordinates(&p).map_err(|m| bad(body, m))?;
                data.positions.push(p);
                if let (Some(n), Some(normals)) = (normal_props, data.normals.as_mut()) {
                    normals.push(n.map(|k| values[k]));
                }
            }
        }
    }
    body.finish()?;
    Ok(data)
}

/// `stop` with a message that names the property `p` it is about.
fn named(p: &Property, stop: Stop) -> Stop {
    match stop {
        Stop::Bad(m) => Stop::Bad(format!("property {}: {m}", p.name)),
        end => end,
    }
}

/// Reads a face's `n` vertex indices (of the list `list`) into `data`: 3 to 65 535 of
/// them, each below the file's `nv` vertices.
fn read_face<B: Body>(
    body: &mut B,
    list: &Property,
    n: usize,
    nv: u64,
    data: &mut PlyData,
) -> Result<(), Stop> {
    if !(3..=usize::from(u16::MAX)).contains(&n) {
        return Err(Stop::Bad(match n {
            0..=2 => format!("has {n} vertices; a face needs at least 3"),
            _ => format!("has {n} vertices; a face may have at most 65535"),
        }));
    }
    for _ in 0..n {
        let index = body.value(list.ty).map_err(|e| named(list, e))?;
        if index < 0.0 || index >= nv as f64 {
            return Err(Stop::Bad(format!(
                "vertex index {index} is out of range: the file has {nv} vertices (PLY \
                 indices start at 0)"
            )));
        }
        // An integer of PLY's types (at most 32 bits) in `0..nv`.
        data.face_verts.push(index as u32);
    }
    let corners = u32::try_from(data.face_verts.len())
        .map_err(|_| Stop::Bad("too many face corners for 32-bit indices".into()))?;
    data.face_offsets.push(corners);
    if let Some(line) = body.line() {
        data.face_lines
            .push(u32::try_from(line).unwrap_or(u32::MAX));
    }
    Ok(())
}

/// A vertex's coordinates must be finite and below [`MAX_COORDINATE`] in magnitude.
fn check_coordinates(p: &[f64; 3]) -> Result<(), String> {
    if let Some(c) = p.iter().find(|c| !c.is_finite()) {
        return Err(format!("non-finite coordinate {c}"));
    }
    if let Some(c) = p.iter().find(|c| c.abs() >= MAX_COORDINATE) {
        return Err(format!(
            "the coordinate {c:e} is too large; coordinates must be below 1e75 in magnitude"
        ));
    }
    Ok(())
}
