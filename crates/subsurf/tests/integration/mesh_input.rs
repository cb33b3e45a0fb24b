//! `io::input`: a mesh from a stream in blocks, told apart by content, within a memory
//! limit. The streams here count the bytes they give, so the tests see how far the reader
//! read (no timing).

use std::cell::Cell;
use std::io::{self, Read};
use std::rc::Rc;

use subsurf::io::parse_obj;
use subsurf::io::PlyEncoding;
use subsurf::io::{parse_mesh, read_mesh_from, MeshFormat, ReadMeshError, BLOCK};

/// A stream of `head`, then `tail` repeated without end, counting the bytes it gives.
struct Endless {
    head: Vec<u8>,
    tail: Vec<u8>,
    at: usize,
    given: Rc<Cell<u64>>,
}

impl Endless {
    fn new(head: &[u8], tail: &[u8]) -> (Self, Rc<Cell<u64>>) {
        let given = Rc::new(Cell::new(0));
        let s = Self {
            head: head.to_vec(),
            tail: tail.to_vec(),
            at: 0,
            given: given.clone(),
        };
        (s, given)
    }
}

impl Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        for b in buf.iter_mut() {
            *b = match self.head.get(self.at) {
                Some(&b) => b,
                None => self.tail[(self.at - self.head.len()) % self.tail.len()],
            };
            self.at += 1;
        }
        self.given.set(self.given.get() + buf.len() as u64);
        Ok(buf.len())
    }
}

/// A stream that must not be read.
struct Untouchable;

impl Read for Untouchable {
    fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
        panic!("read although the size alone is refused");
    }
}

#[track_caller]
fn obj_error(r: Result<impl std::fmt::Debug, ReadMeshError>) -> (Option<usize>, String) {
    match r {
        Err(ReadMeshError::Obj(e)) => (e.line, e.to_string()),
        other => panic!("expected an OBJ error, got {other:?}"),
    }
}

/// An endless stream of NUL bytes (`subsurf info` of 3 GB of them used 2.8 GiB) is
/// refused at line 1 after its first block; so is one of bytes that are not UTF-8 after
/// 3 MiB of valid lines, at its first line, after one more block.
#[test]
fn binary_streams_stop_at_their_first_block() {
    let (zeros, given) = Endless::new(b"", b"\0");
    let (line, shown) = obj_error(read_mesh_from(zeros, "<stdin>", None, None));
    assert_eq!(line, Some(1));
    assert_eq!(
        shown,
        "<stdin>:1: line 1 contains the control character 0x00 (is this a binary file?)"
    );
    assert!(given.get() <= BLOCK as u64, "read {} bytes", given.get());

    let head = b"v 0 0 0\n".repeat(3 << 17); // 3 MiB, 393 216 lines
    let (garbage, given) = Endless::new(&head, b"\xff\xfe");
    let (line, shown) = obj_error(read_mesh_from(garbage, "in.obj", None, None));
    assert_eq!(line, Some(393_217));
    assert!(shown.ends_with("line 393217 is not valid UTF-8"), "{shown}");
    assert!(given.get() <= head.len() as u64 + BLOCK as u64);
}

/// The body of an ASCII PLY file is checked as text too: NUL bytes after two records stop
/// the reading at their line, after one block; a binary body is read as binary.
#[test]
fn ascii_ply_streams_stop_at_their_first_block() {
    let head = b"ply\nformat ascii 1.0\nelement vertex 1000000\nproperty float x\n\
                 property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n";
    let (s, given) = Endless::new(head, b"\0");
    match read_mesh_from(s, "scan.ply", None, None) {
        Err(ReadMeshError::Ply(e)) => assert_eq!(
            e.to_string(),
            "scan.ply:10: vertex 2: line 10 contains the control character 0x00 (is this a \
             binary file?)"
        ),
        other => panic!("{other:?}"),
    }
    assert!(given.get() <= BLOCK as u64);
    let binary = String::from_utf8_lossy(head).replace("ascii", "binary_little_endian");
    let end = binary.find("0 0 0").unwrap();
    let mut bytes = binary.as_bytes()[..end].to_vec();
    bytes.extend_from_slice(&[0; 12 * 1000]);
    match read_mesh_from(&bytes[..], "scan.ply", None, None) {
        Err(ReadMeshError::Ply(e)) => assert_eq!(
            e.to_string(),
            "scan.ply: the file ends in element vertex after 1000 of its 1000000 records (is \
             it truncated?)"
        ),
        other => panic!("{other:?}"),
    }
}

/// The error is the whole file's: an earlier problem is reported first; a line's first
/// byte that is not text decides the message, also when a block cuts a UTF-8 sequence.
#[test]
fn the_first_problem_of_the_file_is_reported() {
    let (s, _) = Endless::new(b"v 0 0 0\nv 1 x 0\n", b"\0");
    let (line, shown) = obj_error(read_mesh_from(s, "a.obj", None, None));
    assert_eq!(
        (line, shown.as_str()),
        (Some(2), "a.obj:2: v: 'x' is not a number")
    );
    // A comment of two-byte characters across the end of the first block, then a NUL.
    let mut head = b"v 0 0 0\n#".to_vec();
    while head.len() < BLOCK + 10 {
        head.extend_from_slice("é".as_bytes());
    }
    head.extend_from_slice(b"\n# \x01 \xff\n");
    let whole = head.clone();
    assert!(
        std::str::from_utf8(&head[..BLOCK]).is_err(),
        "the block cuts a character"
    );
    let (s, _) = Endless::new(&head, b"\0");
    let (line, shown) = obj_error(read_mesh_from(s, "a.obj", None, None));
    assert_eq!(line, Some(3));
    assert!(shown.contains("control character 0x01"), "{shown}");
    // The same bytes parsed whole: the same message (the control character comes first
    // in its line, before the byte that is not UTF-8).
    let e = parse_obj(&whole, "a.obj").unwrap_err();
    assert_eq!(e.to_string(), shown);
}

/// An endless stream of valid lines stops once its bytes pass the limit; a size above
/// the limit is refused before anything is read; a file whose bytes fit but not with the
/// lists parsed from them is refused before they are built, and read with a higher limit.
#[test]
fn input_counts_against_the_limit() {
    let limit = 1 << 20;
    let (s, given) = Endless::new(b"", b"v 0 0 0\n");
    match read_mesh_from(s, "<stdin>", None, Some(limit)) {
        Err(ReadMeshError::TooLarge {
            needed,
            limit: l,
            whole: false,
            ..
        }) => assert!(needed > limit && l == limit),
        other => panic!("{other:?}"),
    }
    assert!(given.get() <= limit + BLOCK as u64, "read {}", given.get());

    let e = read_mesh_from(Untouchable, "big.obj", Some(limit + 1), Some(limit)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "big.obj: reading the mesh needs at least 1048577 bytes, more than the limit of 1048576"
    );

    // 600 kB of vertices: 75 000 vertices of 24 bytes, held twice at the peak.
    let text = b"v 0 0 0\n".repeat(75_000);
    match read_mesh_from(&text[..], "v.obj", Some(text.len() as u64), Some(limit)) {
        Err(ReadMeshError::TooLarge {
            needed,
            whole: true,
            ..
        }) => assert_eq!(needed, 600_000 + 2 * 24 * 75_000),
        other => panic!("{other:?}"),
    }
    let f = read_mesh_from(&text[..], "v.obj", None, Some(8 * limit)).unwrap();
    assert_eq!(f.obj.mesh.num_vertices(), 75_000);
}

/// Read in blocks, any OBJ gives what `parse_obj` gives (the OBJ regression shapes, and
/// one file of 5 MiB: several blocks, read in parallel chunks).
#[test]
fn blocks_read_as_parse_obj_reads() {
    let dir = crate::common::osd_shapes_dir();
    let mut big = Vec::new();
    for name in ["catmark_pawn", "catmark_car", "catmark_bishop"] {
        let bytes = std::fs::read(dir.join(format!("{name}.obj"))).unwrap();
        let one = parse_obj(&bytes, name).unwrap();
        let f = read_mesh_from(&bytes[..], name, None, Some(1 << 30)).unwrap();
        assert_eq!(f.format, MeshFormat::Obj);
        assert_eq!(format!("{:?}", f.obj), format!("{one:?}"));
        big = bytes;
    }
    while big.len() < 5 * BLOCK {
        big.extend_from_slice(b"v 1 2 3\r\nvn 0 0 1\n# a comment\n");
    }
    let one = parse_obj(&big, "big").unwrap();
    let f = read_mesh_from(&big[..], "big", None, None).unwrap();
    assert_eq!(format!("{:?}", f.obj), format!("{one:?}"));
}

/// The reader follows the content: PLY by its first line whatever the name; other
/// formats by their signature or, failing that, their extension, with a message that
/// names the formats read; a `.ply` file without the `ply` line is not PLY.
#[test]
fn the_format_is_told_by_content() {
    let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for name in ["mesh.obj", "<stdin>", "mesh.ply", "mesh"] {
        let f = parse_mesh(ply, name).unwrap();
        assert_eq!(f.format, MeshFormat::Ply(PlyEncoding::Ascii));
        assert_eq!(f.obj.mesh.num_faces(), 1);
        assert_eq!(f.obj.face_lines, [13]);
    }
    let unsupported = |bytes: &[u8], name: &str, what: &str| match parse_mesh(bytes, name) {
        Err(e @ ReadMeshError::Unsupported { .. }) => {
            let shown = e.to_string();
            assert!(
                shown.starts_with(&format!("{name}: this looks like {what};"))
                    && shown.contains(
                        "meshes are read from OBJ, PLY and glTF (.gltf, .glb) files only"
                    ),
                "{shown}"
            );
        }
        other => panic!("{name}: {other:?}"),
    };
    unsupported(b"Kaydara FBX Binary  \0", "x", "an FBX file");
    unsupported(b"PXR-USDC", "x", "a USD file");
    unsupported(
        b"  {\"type\": \"nurbs\"}",
        "curves.json",
        "a JSON file (not glTF)",
    );
    unsupported(b"solid x\nfacet normal 0 0 1\n", "<stdin>", "an STL file");
    unsupported(b"OFF\n3 1 0\n", "x.txt", "an OFF file");
    unsupported(b"\x00\x01binary", "part.STL", "an STL file");
    // glTF by content, whatever the name; not glTF under its name: refused as not glTF.
    for (bytes, name, message) in [
        (
            &b"glTF\x02\0\0\0"[..],
            "x.obj",
            "x.obj: the binary glTF file is cut short (8 bytes)",
        ),
        (
            b"  {\"asset\": {}}",
            "scene",
            "scene: not valid glTF JSON: missing field `version`",
        ),
        (
            b"v 0 0 0\n",
            "x.glb",
            "x.glb: not a binary glTF file: it does not start with 'glTF'",
        ),
        (
            b"v 0 0 0\n",
            "x.gltf",
            "x.gltf: not a glTF file: it is not a JSON object (it does not start with '{')",
        ),
    ] {
        let e = parse_mesh(bytes, name).unwrap_err().to_string();
        assert!(e.starts_with(message), "{e}");
    }
    match parse_mesh(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "x.ply") {
        Err(ReadMeshError::Ply(e)) => {
            assert_eq!(
                e.to_string(),
                "x.ply:1: not a PLY file: the first line is not 'ply'"
            )
        }
        other => panic!("{other:?}"),
    }
    // Old Mac OS line ends.
    let f = parse_mesh(b"v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r", "mac.obj").unwrap();
    assert_eq!(f.obj.mesh.num_faces(), 1);
    assert_eq!(f.obj.face_lines, [4]);
}
