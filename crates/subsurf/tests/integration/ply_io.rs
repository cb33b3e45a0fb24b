//! The PLY reader as a specification: the three encodings give the same mesh as the OBJ
//! of it, every numeric type of coordinates, counts and indices is read, other properties
//! and elements are read past (and listed), and every malformed file is an error naming
//! the file and the line (header, ASCII records) or the element and record (binary
//! records), never a panic or a misread mesh.

use subsurf::io::parse_obj;
use subsurf::io::{parse_ply, read_ply, write_ply, PlyEncoding, PlyError};
use subsurf::mesh::PolyMesh;

use crate::common::{osd_shapes_dir, Rng};

const NAME: &str = "test.ply";

/// A PLY property type and how its values are written.
#[derive(Clone, Copy)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn name(self) -> &'static str {
        [
            "char", "uchar", "short", "ushort", "int", "uint", "float", "double",
        ][self as usize]
    }

    fn bytes(self, x: f64, big: bool) -> Vec<u8> {
        let mut b = match self {
            Ty::I8 => (x as i8).to_le_bytes().to_vec(),
            Ty::U8 => (x as u8).to_le_bytes().to_vec(),
            Ty::I16 => (x as i16).to_le_bytes().to_vec(),
            Ty::U16 => (x as u16).to_le_bytes().to_vec(),
            Ty::I32 => (x as i32).to_le_bytes().to_vec(),
            Ty::U32 => (x as u32).to_le_bytes().to_vec(),
            Ty::F32 => (x as f32).to_le_bytes().to_vec(),
            Ty::F64 => x.to_le_bytes().to_vec(),
        };
        if big {
            b.reverse();
        }
        b
    }

    fn text(self, x: f64) -> String {
        match self {
            Ty::F32 => format!("{}", x as f32),
            _ => format!("{x}"),
        }
    }
}

/// How a test file is laid out: the types of `x y z`, of the face list's count and
/// indices, its name, and extra properties and elements (read past).
#[derive(Clone, Copy)]
struct Layout {
    coord: [Ty; 3],
    count: Ty,
    index: Ty,
    list_name: &'static str,
    extras: bool,
}

const PLAIN: Layout = Layout {
    coord: [Ty::F64; 3],
    count: Ty::U8,
    index: Ty::I32,
    list_name: "vertex_indices",
    extras: false,
};

/// `mesh` as a PLY file in `encoding` with `layout`. With extras: a `confidence` float
/// and a `tags` list (ushort count, int items) on the vertices, a `flags` int before the
/// faces' list and a `texcoord` float list after it, and an element `edge` (a list and a
/// double per record) between the vertices and the faces.
fn ply(mesh: &PolyMesh, encoding: PlyEncoding, layout: Layout) -> Vec<u8> {
    let nv = mesh.num_vertices();
    let mut h = format!("ply\nformat {encoding} 1.0\ncomment made by a test\n");
    h += &format!("element vertex {nv}\n");
    for (ty, c) in layout.coord.iter().zip(["x", "y", "z"]) {
        h += &format!("property {} {c}\n", ty.name());
    }
    if layout.extras {
        h += "property float confidence\nproperty list ushort int tags\n";
        h += "element edge 2\nproperty list uchar uint vertices\nproperty double crease\n";
    }
    h += &format!("element face {}\n", mesh.num_faces());
    if layout.extras {
        h += "property int flags\n";
    }
    h += &format!(
        "property list {} {} {}\n",
        layout.count.name(),
        layout.index.name(),
        layout.list_name
    );
    if layout.extras {
        h += "property list uchar float texcoord\n";
    }
    h += "end_header\n";
    let mut out = h.into_bytes();
    let big = encoding == PlyEncoding::BinaryBigEndian;
    let mut record = |values: &[(Ty, f64)]| {
        if encoding == PlyEncoding::Ascii {
            let words: Vec<String> = values.iter().map(|&(t, x)| t.text(x)).collect();
            out.extend_from_slice(words.join(" ").as_bytes());
            out.push(b'\n');
        } else {
            for &(t, x) in values {
                out.extend_from_slice(&t.bytes(x, big));
            }
        }
    };
    for (i, p) in mesh.positions().iter().enumerate() {
        let mut v: Vec<(Ty, f64)> = (0..3).map(|k| (layout.coord[k], p[k])).collect();
        if layout.extras {
            v.extend([(Ty::F32, 0.5), (Ty::U16, (i % 3) as f64)]);
            v.extend((0..i % 3).map(|k| (Ty::I32, k as f64 - 7.0)));
        }
        record(&v);
    }
    if layout.extras {
        record(&[
            (Ty::U8, 2.0),
            (Ty::U32, 0.0),
            (Ty::U32, 1.0),
            (Ty::F64, 2.5),
        ]);
        record(&[(Ty::U8, 0.0), (Ty::F64, f64::NAN)]);
    }
    for f in mesh.faces() {
        let mut v = Vec::new();
        if layout.extras {
            v.push((Ty::I32, -3.0));
        }
        v.push((layout.count, f.len() as f64));
        v.extend(f.iter().map(|&i| (layout.index, f64::from(i))));
        if layout.extras {
            v.push((Ty::U8, 2.0 * f.len() as f64));
            v.extend((0..2 * f.len()).map(|k| (Ty::F32, k as f64 / 8.0)));
        }
        record(&v);
    }
    out
}

/// OpenSubdiv's pawn (quads and more) without its tags and texture coordinates, which
/// these PLY files do not hold.
fn pawn() -> PolyMesh {
    let path = osd_shapes_dir().join("catmark_pawn.obj");
    let text = std::fs::read(&path).expect("shape file");
    let mut mesh = parse_obj(&text[..], "pawn").expect("valid OBJ").mesh;
    mesh.tags = Default::default();
    mesh.face_varying.clear();
    mesh
}

const ENCODINGS: [PlyEncoding; 3] = [
    PlyEncoding::Ascii,
    PlyEncoding::BinaryLittleEndian,
    PlyEncoding::BinaryBigEndian,
];

/// The same mesh (the pawn: quads and more, 3 significant digits and full doubles) as
/// PLY in each encoding reads back as the OBJ reader read it, bit for bit; ASCII faces
/// have their lines.
#[test]
fn encodings_read_as_the_obj() {
    let obj = pawn();
    for encoding in ENCODINGS {
        let bytes = ply(&obj, encoding, PLAIN);
        let f = parse_ply(&bytes, NAME).unwrap_or_else(|e| panic!("{encoding}: {e}"));
        assert_eq!(f.encoding, encoding);
        assert_eq!(f.mesh, obj, "{encoding}");
        assert!(f.ignored.is_empty(), "{:?}", f.ignored);
        if encoding == PlyEncoding::Ascii {
            // 10 header lines, then one line per vertex, then the faces.
            let first = 10 + obj.num_vertices() as u32 + 1;
            let want: Vec<u32> = (first..).take(obj.num_faces()).collect();
            assert_eq!(f.face_lines, want);
        } else {
            assert!(f.face_lines.is_empty());
        }
    }
}

/// Every numeric type for coordinates (integers exactly; `float` rounded to single
/// precision, as stored, the same from ASCII text as from binary), every integer type for
/// counts and indices, `vertex_index` as well as `vertex_indices`, and other properties
/// and elements (lists of any type in any element, an element between the vertices and
/// the faces) read past and listed in `ignored`.
#[test]
fn every_type_and_what_is_read_past() {
    // Values every type of their column holds: y in char's range, z in uchar's.
    let p = vec![
        [0.1, -128.0, 0.0],
        [1.0 / 3.0, 127.0, 255.0],
        [-2.5, 3.0, 200.0],
        [7.0, 0.0, 1.0],
    ];
    let mesh = PolyMesh::from_faces(p.clone(), &[vec![0, 1, 2, 3], vec![3, 2, 1]]).unwrap();
    let coords = [
        [Ty::F32, Ty::I8, Ty::U8],
        [Ty::F64, Ty::I16, Ty::U16],
        [Ty::F32, Ty::I32, Ty::U32],
    ];
    let lists = [
        (Ty::U8, Ty::U8),
        (Ty::I8, Ty::I16),
        (Ty::U16, Ty::U16),
        (Ty::I16, Ty::U32),
        (Ty::U32, Ty::I32),
        (Ty::I32, Ty::U8),
    ];
    for encoding in ENCODINGS {
        for coord in coords {
            for (i, &(count, index)) in lists.iter().enumerate() {
                let layout = Layout {
                    coord,
                    count,
                    index,
                    list_name: ["vertex_indices", "vertex_index"][i % 2],
                    extras: i % 3 != 0,
                };
                let bytes = ply(&mesh, encoding, layout);
                let f = parse_ply(&bytes, NAME)
                    .unwrap_or_else(|e| panic!("{encoding} {}: {e}", coord[0].name()));
                // `float` holds single precision: 0.1 and 1/3 are rounded, the rest exact.
                let want: Vec<[f64; 3]> = (p.iter())
                    .map(|q| {
                        let x = match coord[0] {
                            Ty::F32 => f64::from(q[0] as f32),
                            _ => q[0],
                        };
                        [x, q[1], q[2]]
                    })
                    .collect();
                assert_eq!(f.mesh.positions(), &want[..], "{encoding}");
                let faces: Vec<Vec<u32>> = f.mesh.faces().map(<[u32]>::to_vec).collect();
                assert_eq!(faces, [vec![0, 1, 2, 3], vec![3, 2, 1]]);
                let ignored = match layout.extras {
                    true => vec![
                        "vertex properties confidence, tags",
                        "element edge (2 records)",
                        "face properties flags, texcoord",
                    ],
                    false => vec![],
                };
                assert_eq!(f.ignored, ignored);
            }
        }
    }
}

/// Elements in any order: faces before the vertices they use.
#[test]
fn faces_before_vertices() {
    let text = "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int \
                vertex_indices\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nend_header\n3 0 1 2\n0 0 0\n1 0 0\n\n0 1 0\n";
    let f = parse_ply(text.as_bytes(), NAME).unwrap();
    assert_eq!(f.mesh.face(0), &[0, 1, 2]);
    assert_eq!(f.mesh.positions()[2], [0.0, 1.0, 0.0]);
    assert_eq!(f.face_lines, [10]);
    // CRLF and CR line ends, in the header and in the body.
    let crlf = text.replace('\n', "\r\n");
    assert_eq!(parse_ply(crlf.as_bytes(), NAME).unwrap(), f);
    let cr = format!(
        "{}{}",
        &crlf[..crlf.find("end_header").unwrap() + 12],
        text[text.find("end_header").unwrap() + 11..].replace('\n', "\r")
    );
    assert_eq!(parse_ply(cr.as_bytes(), NAME).unwrap(), f);
}

/// What `write_ply` writes `read_ply` reads back, normals included.
#[test]
fn written_files_read_back() {
    let mesh = pawn();
    let normals: Vec<[f64; 3]> = (0..mesh.num_vertices())
        .map(|i| [i as f64, 0.5, -1.0])
        .collect();
    let mut out = Vec::new();
    let (o, v) = (mesh.face_offsets(), mesh.face_verts());
    write_ply(&mut out, mesh.positions(), Some(&normals), o, v).unwrap();
    let back = read_ply(&out).unwrap();
    assert_eq!(back.positions, mesh.positions());
    assert_eq!(back.normals.as_deref(), Some(&normals[..]));
    assert_eq!((&back.face_offsets[..], &back.face_verts[..]), (o, v));
    let f = parse_ply(&out, NAME).unwrap();
    assert_eq!(f.mesh, mesh);
    assert_eq!(f.ignored, ["vertex properties nx, ny, nz"]);
}

/// `text` fails with `message` (and, for `Some`, at `line`).
#[track_caller]
fn assert_error(bytes: &[u8], line: Option<usize>, message: &str) -> PlyError {
    let e = match parse_ply(bytes, NAME) {
        Ok(_) => panic!("expected an error containing {message:?}"),
        Err(e) => e,
    };
    let shown = e.to_string();
    assert_eq!(e.line, line, "{shown}");
    let at = line.map(|l| format!(":{l}")).unwrap_or_default();
    assert!(shown.starts_with(&format!("{NAME}{at}: ")), "{shown}");
    assert!(shown.contains(message), "{shown:?} lacks {message:?}");
    e
}

const HEAD: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                    end_header\n";
const TRI: &str = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";

#[test]
fn header_errors_name_their_line() {
    let ok = format!("{HEAD}{TRI}");
    assert!(parse_ply(ok.as_bytes(), NAME).is_ok());
    let cases: [(&str, &str, Option<usize>, &str); 11] = [
        ("ply\n", "plyx\n", Some(1), "the first line is not 'ply'"),
        ("ascii 1.0", "ascii 2.0", Some(2), "only version 1.0"),
        (
            "ascii 1.0",
            "ebcdic 1.0",
            Some(2),
            "unknown PLY format 'ebcdic 1.0'",
        ),
        ("format ascii 1.0\n", "", None, "no format line"),
        (
            "element vertex 3",
            "element vertex -3",
            Some(3),
            "'-3' is not a count",
        ),
        (
            "element vertex 3",
            "element vertex",
            Some(3),
            "malformed element line",
        ),
        ("float y", "half y", Some(5), "unknown PLY type 'half'"),
        ("float y", "float x", Some(5), "lists property 'x' twice"),
        (
            "uchar int",
            "float int",
            Some(8),
            "count type float is not an integer type",
        ),
        (
            "uchar int",
            "uchar float",
            Some(7),
            "holds float values, not integer indices",
        ),
        (
            "element face 1\n",
            "element face 1\nelement face 1\n",
            Some(8),
            "a second element",
        ),
    ];
    for (from, to, line, message) in cases {
        let text = ok.replacen(from, to, 1);
        assert_error(text.as_bytes(), line, message);
    }
    let text = ok.replacen("property float z\n", "", 1);
    assert_error(text.as_bytes(), Some(3), "element vertex has no property z");
    let text = ok.replacen("property float z\n", "property list uchar float z\n", 1);
    assert_error(
        text.as_bytes(),
        Some(3),
        "property z of element vertex is a list",
    );
    let text = ok.replacen("vertex_indices", "corners", 1);
    assert_error(
        text.as_bytes(),
        Some(7),
        "element face has no vertex_indices",
    );
    let text = ok.replacen("element vertex 3", "element point 3", 1);
    assert_error(text.as_bytes(), Some(9), "no vertex element");
    let text = ok
        .replacen("comment", "", 1)
        .replacen("ascii 1.0\n", "ascii 1.0\nbogus\n", 1);
    assert_error(
        text.as_bytes(),
        Some(3),
        "unknown PLY header keyword 'bogus'",
    );
    let text = ok.replacen("end_header\n", "element empty 5\nend_header\n", 1);
    assert_error(
        text.as_bytes(),
        Some(9),
        "element empty has 5 records but no properties",
    );
    // Without end_header, the records would be header lines; a header cut short is
    // incomplete.
    let text = ok.replacen("end_header\n", "", 1);
    assert_error(text.as_bytes(), Some(9), "unknown PLY header keyword '0'");
    assert_error(
        HEAD.replacen("end_header\n", "", 1).as_bytes(),
        None,
        "no end_header",
    );
    let text = ok.replacen("\nformat", "\ncomment \x01\nformat", 1);
    assert_error(text.as_bytes(), Some(2), "control character 0x01");
    // A header longer than the limit without end_header is not read to its end.
    let mut long = b"ply\nformat ascii 1.0\n".to_vec();
    long.resize(subsurf::io::MAX_HEADER + 100, b'\n');
    assert_error(&long, None, "no end_header line in its first 1024 KiB");
}

#[test]
fn ascii_record_errors_name_their_line_and_record() {
    let cases: [(&str, usize, &str); 10] = [
        (
            "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n",
            11,
            "vertex 1: property y: 'x' is not a number",
        ),
        (
            "0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
            11,
            "vertex 1: property z: the line has fewer",
        ),
        (
            "0 0 0\n1 0 0 9\n0 1 0\n3 0 1 2\n",
            11,
            "vertex 1: the line has more values",
        ),
        (
            "0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n",
            11,
            "vertex 1: non-finite coordinate inf",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            13,
            "face 0: vertex index 3 is out of range",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
            13,
            "face 0: vertex index -1 is out of range",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n",
            13,
            "'1.5' is not an integer (int)",
        ),
        (
            "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n",
            13,
            "-3 is out of the range of uchar",
        ),
        ("0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 13, "face 0: has 2 vertices"),
        (
            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n",
            14,
            "data after the last record",
        ),
    ];
    for (body, line, message) in cases {
        assert_error(format!("{HEAD}{body}").as_bytes(), Some(line), message);
    }
    // A float coordinate beyond f32 is infinite as the type holds it.
    let text = format!("{HEAD}0 0 0\n1e39 0 0\n0 1 0\n3 0 1 2\n");
    assert_error(text.as_bytes(), Some(11), "non-finite coordinate inf");
    let text = format!("{HEAD}0 0 0\n1 0 0\n");
    assert_error(
        text.as_bytes(),
        None,
        "ends in element vertex after 2 of its 3 records",
    );
    let text = format!("{HEAD}0 0 0\n1 0 0\n0 \u{0}1 0\n3 0 1 2\n");
    assert_error(
        text.as_bytes(),
        Some(12),
        "line 12 contains the control character 0x00",
    );
    let mut bytes = format!("{HEAD}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").into_bytes();
    bytes[HEAD.len() + 7] = 0xff;
    assert_error(&bytes, Some(11), "line 11 is not valid UTF-8");
}

/// Binary files cut anywhere are refused (the record where the file ends), never
/// misread; with extra bytes too; indices out of range name the face.
#[test]
fn binary_record_errors_name_the_record() {
    let mesh = pawn();
    for encoding in [
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian,
    ] {
        let layout = Layout {
            extras: true,
            ..PLAIN
        };
        let bytes = ply(&mesh, encoding, layout);
        let body = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        for cut in (body..bytes.len()).step_by(37).chain([bytes.len() - 1]) {
            let e = assert_error(&bytes[..cut], None, "(is it truncated?)");
            assert!(e.message.starts_with("the file ends in element "), "{e}");
        }
        let mut more = bytes.clone();
        more.extend_from_slice(&[0; 3]);
        assert_error(&more, None, "3 bytes after the last record");
    }
    let quad = PolyMesh::from_faces(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2, 3], [0, 1, 2, 3]],
    )
    .unwrap();
    let mut bytes = ply(&quad, PlyEncoding::BinaryBigEndian, PLAIN);
    let n = bytes.len();
    bytes[n - 4..].copy_from_slice(&7i32.to_be_bytes());
    assert_error(
        &bytes,
        None,
        "face 1: vertex index 7 is out of range: the file has 4",
    );
    bytes[n - 4..].copy_from_slice(&(-2i32).to_be_bytes());
    assert_error(&bytes, None, "face 1: vertex index -2 is out of range");
    let mut bytes = ply(&quad, PlyEncoding::BinaryLittleEndian, PLAIN);
    let x = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11
        + 24;
    bytes[x..x + 8].copy_from_slice(&f64::NAN.to_le_bytes());
    assert_error(&bytes, None, "vertex 1: non-finite coordinate NaN");
    bytes[x..x + 8].copy_from_slice(&(-1e75f64).to_le_bytes());
    assert_error(&bytes, None, "vertex 1: the coordinate -1e75 is too large");
}

/// Random damage to valid files (bytes changed, lines dropped or repeated) gives the mesh
/// or an error naming the file, never a panic; and what is read is a valid mesh.
#[test]
fn damaged_files_never_panic() {
    let mesh = pawn();
    let mut rng = Rng(0x5eed);
    let mut below = |n: usize| ((rng.next() + 0.5) * n as f64) as usize % n.max(1);
    for encoding in ENCODINGS {
        let good = ply(
            &mesh,
            encoding,
            Layout {
                extras: true,
                ..PLAIN
            },
        );
        for _ in 0..300 {
            let mut bytes = good.clone();
            for _ in 0..1 + below(3) {
                let at = below(bytes.len());
                match below(3) {
                    0 => bytes[at] = below(256) as u8,
                    1 => {
                        bytes.remove(at);
                    }
                    _ => bytes.insert(at, b"0 \n\xff"[below(4)]),
                }
            }
            match parse_ply(&bytes, NAME) {
                Ok(f) => f.mesh.validate().expect("a valid mesh"),
                Err(e) => assert!(e.to_string().starts_with(NAME), "{e}"),
            }
        }
    }
}
