//! glTF input (`io::parse_gltf`, and `.gltf`/`.glb` through `io::read_mesh`): files built
//! here by hand (JSON with `serde_json`, buffers of little-endian `f32`/`u32`), read back
//! welded with `TEXCOORD_0` as the channel `"uv"`, compared with the same mesh read from
//! OBJ; bad files give errors that name what is at fault, and garbled bytes never panic.

use std::collections::BTreeMap;

use serde_json::{json, Value};
use subsurf::io::{parse_gltf, parse_mesh, parse_obj, read_mesh, MeshFormat, Up};
use subsurf::mesh::PolyMesh;
use subsurf::{subdivide, SubdivideOptions};

/// One primitive: positions, optional texture coordinates and indices, its mode.
#[derive(Clone, Default)]
struct Prim {
    positions: Vec<[f32; 3]>,
    uv: Option<Vec<[f32; 2]>>,
    indices: Option<Vec<u32>>,
    /// glTF's mode (4: TRIANGLES when `None`).
    mode: Option<u32>,
    /// More attributes, as (name, accessor type, values).
    extra: Vec<(&'static str, &'static str, Vec<f32>)>,
}

/// A glTF document of one mesh of `prims`, placed by one node with `node` (a JSON object
/// holding e.g. a `matrix`), and its buffer.
fn document(prims: &[Prim], node: Value) -> (Value, Vec<u8>) {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut add = |bytes: Vec<u8>, count: usize, kind: &str, component: u32| {
        let view = views.len();
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend_from_slice(&bytes);
        accessors.push(
            json!({"bufferView": view, "componentType": component, "count": count, "type": kind}),
        );
        accessors.len() - 1
    };
    let floats =
        |v: &mut dyn Iterator<Item = f32>| v.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
    let mut primitives = Vec::new();
    for p in prims {
        let n = p.positions.len();
        let mut attributes = serde_json::Map::new();
        let pos = add(
            floats(&mut p.positions.iter().flatten().copied()),
            n,
            "VEC3",
            5126,
        );
        attributes.insert("POSITION".into(), json!(pos));
        if let Some(uv) = &p.uv {
            let a = add(
                floats(&mut uv.iter().flatten().copied()),
                uv.len(),
                "VEC2",
                5126,
            );
            attributes.insert("TEXCOORD_0".into(), json!(a));
        }
        for (name, kind, values) in &p.extra {
            let per = match *kind {
                "VEC2" => 2,
                "VEC3" => 3,
                _ => 4,
            };
            let a = add(
                floats(&mut values.iter().copied()),
                values.len() / per,
                kind,
                5126,
            );
            attributes.insert(name.to_string(), json!(a));
        }
        let mut prim = json!({"attributes": attributes, "mode": p.mode.unwrap_or(4)});
        if let Some(idx) = &p.indices {
            let bytes = idx.iter().flat_map(|i| i.to_le_bytes()).collect();
            prim["indices"] = json!(add(bytes, idx.len(), "SCALAR", 5125));
        }
        primitives.push(prim);
    }
    let mut node = node;
    node["mesh"] = json!(0);
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [node],
        "meshes": [{"primitives": primitives}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    (doc, bin)
}

/// `doc` and `bin` as a GLB file.
fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    for w in [2, total as u32, json.len() as u32, 0x4E4F_534A] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(&0x004E_4942u32.to_le_bytes());
    out.extend_from_slice(&bin);
    out
}

/// `doc` as `.gltf` JSON with `bin` embedded as a base64 data URI.
fn gltf_embedded(doc: &Value, bin: &[u8]) -> Vec<u8> {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::new();
    for c in bin.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                text.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                text.push('=');
            }
        }
    }
    let mut doc = doc.clone();
    doc["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{text}"));
    serde_json::to_vec_pretty(&doc).unwrap()
}

/// The textured cube of the face-varying golden data (`tests/golden/fvar/textured_cube.obj`,
/// without its tags) as an exporter writes glTF: quads split into two triangles
/// (`0 1 2`, `0 2 3`), every face corner a vertex of its own (flat normals split them all),
/// `v = 1 − t`.
/// Positions, texture coordinates, and each quad's (vertex, vt) corners.
type CubeObj = (Vec<[f64; 3]>, Vec<[f64; 2]>, Vec<[(usize, usize); 4]>);

fn cube_obj() -> CubeObj {
    let path = format!(
        "{}/tests/golden/fvar/textured_cube.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let f = parse_obj(&std::fs::read(path).unwrap(), "cube").unwrap();
    let vt = f.texcoords.iter().map(|t| [t[0], t[1]]).collect();
    let tex = f.face_texcoords.unwrap();
    let faces = (0..6)
        .map(|q| {
            let fv = f.mesh.face(q);
            [0, 1, 2, 3].map(|k| (fv[k] as usize, tex[4 * q + k] as usize))
        })
        .collect();
    (f.mesh.positions().to_vec(), vt, faces)
}

fn cube_prim() -> Prim {
    let (p, vt, faces) = cube_obj();
    let mut prim = Prim::default();
    let (mut positions, mut uv, mut indices) = (Vec::new(), Vec::new(), Vec::new());
    for face in &faces {
        let base = positions.len() as u32;
        for &(v, t) in face {
            positions.push(p[v].map(|x| x as f32));
            uv.push([vt[t][0] as f32, (1.0 - vt[t][1]) as f32]);
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|k| base + k));
    }
    prim.positions = positions;
    prim.uv = Some(uv);
    prim.indices = Some(indices);
    prim
}

/// The faces of `m` as an order-free set: each face the list of its corners' position and
/// `"uv"` value (as bits), rotated to start at its least corner.
fn face_set(m: &PolyMesh) -> BTreeMap<Vec<[u64; 5]>, usize> {
    let uv = m.face_varying.iter().find(|c| c.name() == "uv").unwrap();
    let mut set = BTreeMap::new();
    for (f, fv) in m.faces().enumerate() {
        let start = m.face_offsets()[f] as usize;
        let mut corners: Vec<[u64; 5]> = (fv.iter().enumerate())
            .map(|(k, &v)| {
                let p = m.positions()[v as usize].map(|x| (x + 0.0).to_bits());
                let t = uv.value(uv.indices()[start + k] as usize);
                [p[0], p[1], p[2], t[0].to_bits(), t[1].to_bits()]
            })
            .collect();
        let least = (0..corners.len()).min_by_key(|&i| corners[i]).unwrap();
        corners.rotate_left(least);
        *set.entry(corners).or_default() += 1;
    }
    set
}

/// The cube as OBJ triangles with the same diagonals, a `vt` per distinct (vertex, vt)
/// pair, as the reader's values are.
fn cube_triangles_obj() -> PolyMesh {
    let (p, vt, faces) = cube_obj();
    let mut text = String::new();
    for q in &p {
        text += &format!("v {} {} {}\n", q[0], q[1], q[2]);
    }
    let mut pairs: Vec<(usize, usize)> = faces.iter().flatten().copied().collect();
    pairs.sort_unstable();
    pairs.dedup();
    for &(_, t) in &pairs {
        text += &format!("vt {} {}\n", vt[t][0], vt[t][1]);
    }
    let id = |c: (usize, usize)| pairs.binary_search(&c).unwrap() + 1;
    for face in &faces {
        for tri in [[0, 1, 2], [0, 2, 3]] {
            text += "f";
            for k in tri {
                text += &format!(" {}/{}", face[k].0 + 1, id(face[k]));
            }
            text += "\n";
        }
    }
    parse_obj(text.as_bytes(), "tri.obj").unwrap().mesh
}

/// A textured cube written as an exporter writes it (24 vertices, split at every corner)
/// reads back as the connected cube: 8 vertices, 12 triangles, and as many texture
/// values as the OBJ has (vertex, vt) pairs, so that the seams are exactly the OBJ's; every
/// corner has the OBJ's position and `(s, t)` (from `v = 1 − t`). Refined with
/// Catmull-Clark (UVs too), it gives the faces of the same triangles read from OBJ, and
/// with Loop their positions. The
/// base-64 `.gltf` gives the same mesh as the `.glb`.
#[test]
fn textured_cube_reads_welded_with_its_seams() {
    let (doc, bin) = document(&[cube_prim()], json!({}));
    let bytes = glb(&doc, &bin);
    let m = parse_gltf(&bytes, "cube.glb", None, Up::Y).unwrap();
    assert!(m.binary);
    let mesh = &m.mesh;
    assert_eq!((mesh.num_vertices(), mesh.num_faces()), (8, 12));
    assert!(mesh.faces().all(|f| f.len() == 3));
    let uv = &mesh.face_varying[0];
    assert_eq!((uv.name(), uv.dim()), ("uv", 2));
    let reference = cube_triangles_obj();
    assert_eq!(uv.num_values(), reference.face_varying[0].num_values());
    assert_eq!(face_set(mesh), face_set(&reference));
    assert!(
        mesh.check_strict().is_ok(),
        "a closed, consistently oriented cube"
    );
    for levels in [1, 2] {
        let opts = SubdivideOptions {
            levels,
            ..Default::default()
        };
        let a = subdivide(mesh, &opts).unwrap().mesh;
        let b = subdivide(&reference, &opts).unwrap().mesh;
        assert_eq!(face_set(&a), face_set(&b), "level {levels}");
    }
    // Loop refines the triangles too (its positions as from the OBJ triangles).
    let opts = SubdivideOptions {
        levels: 2,
        scheme: subsurf::Scheme::Loop,
        ..Default::default()
    };
    let (a, b) = (
        subdivide(mesh, &opts).unwrap(),
        subdivide(&reference, &opts).unwrap(),
    );
    assert_eq!(a.mesh.num_faces(), 12 * 16);
    let sorted = |m: &PolyMesh| {
        let mut p: Vec<[u64; 3]> = m.positions().iter().map(|p| p.map(f64::to_bits)).collect();
        p.sort_unstable();
        p
    };
    assert_eq!(sorted(&a.mesh), sorted(&b.mesh));
    let text = gltf_embedded(&doc, &bin);
    let j = parse_gltf(&text, "cube.gltf", None, Up::Y).unwrap();
    assert!(!j.binary);
    assert_eq!(j.mesh, m.mesh);
    // Z up (the default of read_mesh): (x, y, z) -> (x, -z, y), exactly.
    let z = parse_mesh(&bytes, "cube.glb").unwrap();
    assert_eq!(z.format, MeshFormat::Gltf { binary: true });
    let turned: Vec<[f64; 3]> = (mesh.positions().iter())
        .map(|p| [p[0], -p[2], p[1]])
        .collect();
    assert_eq!(z.obj.mesh.positions(), &turned[..]);
    assert_eq!(
        z.obj.mesh.faces().collect::<Vec<_>>(),
        mesh.faces().collect::<Vec<_>>()
    );
}

/// Strips and fans make the triangles of the specification's formulas; a node's
/// translation, rotation and scale place the vertices (composed as T·R·S, and a parent's
/// transform before its child's); a mirroring scale reverses the triangles so that their
/// normals keep pointing the same way; points and lines make no faces and are noted.
#[test]
fn modes_and_transforms() {
    let square = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let strip = Prim {
        positions: square.clone(),
        mode: Some(5),
        ..Prim::default()
    };
    let fan = Prim {
        positions: vec![square[0], square[1], square[3], square[2]],
        mode: Some(6),
        ..Prim::default()
    };
    let lines = Prim {
        positions: square.clone(),
        mode: Some(1),
        ..Prim::default()
    };
    for prims in [vec![strip.clone(), lines.clone()], vec![fan.clone()]] {
        let (doc, bin) = document(&prims, json!({}));
        let m = parse_gltf(&glb(&doc, &bin), "sq.glb", None, Up::Y).unwrap();
        assert_eq!(m.mesh.num_faces(), 2);
        assert_eq!(m.mesh.num_vertices(), 4);
        assert!(m.mesh.check_strict().is_ok());
        for f in m.mesh.faces() {
            let p = |i: usize| m.mesh.positions()[f[i] as usize];
            let (a, b, c) = (p(0), p(1), p(2));
            let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(cross > 0.0, "counter-clockwise seen from +z");
        }
        let notes = m.ignored.join("\n");
        assert_eq!(
            notes.contains("points or lines"),
            prims.len() == 2,
            "{notes}"
        );
    }
    // A parent that translates, a child that scales by (2, 3, -1) (a mirror) after a
    // quarter turn about z.
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let child = json!({"rotation": [0.0, 0.0, s, s], "scale": [2.0, 3.0, -1.0]});
    let (mut doc, bin) = document(&[strip], child);
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({"translation": [10.0, 0.0, 0.0], "children": [0]}));
    doc["scenes"][0]["nodes"] = json!([1]);
    let m = parse_gltf(&glb(&doc, &bin), "t.glb", None, Up::Y)
        .unwrap()
        .mesh;
    // (x, y, 0) -> scale (2x, 3y, 0) -> turn (-3y, 2x, 0) -> translate (10 - 3y, 2x, 0).
    let expected = [[10.0, 0.0], [10.0, 2.0], [7.0, 0.0], [7.0, 2.0]];
    for (p, e) in m.positions().iter().zip(expected) {
        assert!(
            (p[0] - e[0]).abs() < 1e-6 && (p[1] - e[1]).abs() < 1e-6,
            "{p:?}"
        );
    }
    for f in m.faces() {
        let p = |i: usize| m.positions()[f[i] as usize];
        let (a, b, c) = (p(0), p(1), p(2));
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        // The mirror in z takes the front (+z) to -z, and leaves the corners' order in
        // the plane as it is: the triangles are reversed, counter-clockwise from -z.
        assert!(cross < 0.0, "the mirrored triangles are reversed: {f:?}");
    }
}

/// What is not read is noted, one line per kind: normals, other texture coordinates,
/// custom attributes, materials; a primitive without `TEXCOORD_0` beside one with it
/// drops the channel, with a note.
#[test]
fn what_is_left_out_is_noted() {
    let mut cube = cube_prim();
    let n = cube.positions.len();
    cube.extra = vec![
        ("NORMAL", "VEC3", [0.0, 0.0, 1.0].repeat(n)),
        ("TEXCOORD_1", "VEC2", vec![0.5; 2 * n]),
        ("_BATCHID", "VEC2", vec![0.0; 2 * n]),
    ];
    let (mut doc, bin) = document(&[cube.clone()], json!({}));
    doc["materials"] = json!([{}]);
    doc["meshes"][0]["primitives"][0]["material"] = json!(0);
    let m = parse_gltf(&glb(&doc, &bin), "n.glb", None, Up::Y).unwrap();
    let notes = m.ignored.join("\n");
    for kind in ["NORMAL", "TEXCOORD_n", "_NAME", "1 material"] {
        assert!(notes.contains(kind), "{kind}: {notes}");
    }
    assert_eq!(m.ignored.len(), 4, "{notes}");
    assert_eq!(m.mesh.face_varying.len(), 1);
    // A second primitive without texture coordinates.
    let mut bare = cube_prim();
    bare.uv = None;
    for p in &mut bare.positions {
        p[0] += 5.0;
    }
    let (doc, bin) = document(&[cube_prim(), bare], json!({}));
    let m = parse_gltf(&glb(&doc, &bin), "two.glb", None, Up::Y).unwrap();
    assert_eq!(m.mesh.num_vertices(), 16);
    assert!(m.mesh.face_varying.is_empty());
    assert!(
        m.ignored.join("\n").contains("no texture coordinates"),
        "{:?}",
        m.ignored
    );
}

/// An external buffer is read from beside the file (through `read_mesh`, by name), and
/// a missing one names the buffer and the file it looked for.
#[test]
fn external_buffers_are_read_beside_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (mut doc, bin) = document(&[cube_prim()], json!({}));
    doc["buffers"][0]["uri"] = json!("cube%20data.bin");
    std::fs::write(dir.path().join("cube data.bin"), &bin).unwrap();
    let path = dir.path().join("cube.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let f = read_mesh(&path, None).unwrap();
    assert_eq!(f.format, MeshFormat::Gltf { binary: false });
    assert_eq!(f.obj.mesh.num_faces(), 12);
    std::fs::remove_file(dir.path().join("cube data.bin")).unwrap();
    let e = read_mesh(&path, None).unwrap_err().to_string();
    assert!(
        e.contains("buffer 0: cannot read") && e.contains("cube data.bin"),
        "{e}"
    );
    // A limit below the external buffer's bytes refuses it.
    std::fs::write(dir.path().join("cube data.bin"), &bin).unwrap();
    let small = std::fs::metadata(&path).unwrap().len() + 10;
    let e = read_mesh(&path, Some(small)).unwrap_err().to_string();
    assert!(e.contains("more than the limit"), "{e}");
}

/// Bad files give an error that names the file and what is at fault.
#[test]
fn bad_files_name_what_is_at_fault() {
    let (doc, bin) = document(&[cube_prim()], json!({}));
    let check = |doc: &Value, bin: &[u8], expected: &[&str]| {
        let e = parse_gltf(&glb(doc, bin), "bad.glb", None, Up::Z)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("bad.glb: "), "{e}");
        for x in expected {
            assert!(e.contains(x), "{x:?} in {e}");
        }
    };
    let mut d = doc.clone();
    d["meshes"][0]["primitives"][0]["attributes"]
        .as_object_mut()
        .unwrap()
        .remove("POSITION");
    check(&d, &bin, &["mesh 0 (node 0), primitive 0", "no POSITION"]);
    let mut d = doc.clone();
    d["accessors"][0]["type"] = json!("VEC2");
    check(
        &d,
        &bin,
        &["POSITION accessor 0", "VEC2 of f32", "must be VEC3 of f32"],
    );
    let mut d = doc.clone();
    d["accessors"][0]["count"] = json!(1000);
    check(&d, &bin, &["POSITION accessor 0", "beyond its buffer view"]);
    // An index beyond the vertices.
    let mut b = bin.clone();
    let at = b.len() - 4;
    b[at..].copy_from_slice(&99u32.to_le_bytes());
    check(
        &doc,
        &b,
        &["indices accessor 2", "vertex 99", "24 vertices"],
    );
    let mut d = doc.clone();
    d["buffers"][0]["byteLength"] = json!(bin.len() + 400);
    check(&d, &bin, &["buffer 0", "byteLength"]);
    let mut d = doc.clone();
    d["accessors"][0]["bufferView"] = json!(17);
    check(
        &d,
        &bin,
        &["accessor 0 refers to buffer view 17, but the file has 3"],
    );
    let mut d = doc.clone();
    d["nodes"][0]["children"] = json!([0]);
    check(&d, &bin, &["node 0 is reached twice"]);
    let mut d = doc.clone();
    d["meshes"][0]["primitives"][0]["mode"] = json!(0);
    check(&d, &bin, &["no triangles to read", "points or lines"]);
    let mut d = doc.clone();
    d["buffers"][0]["uri"] = json!("https://example.com/x.bin");
    check(&d, &bin, &["buffer 0", "not a relative file name"]);
    let mut d = doc.clone();
    d["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    check(&d, &bin, &["KHR_draco_mesh_compression"]);
    let e = parse_gltf(
        b"{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 3}",
        "j.gltf",
        None,
        Up::Z,
    )
    .unwrap_err();
    assert!(
        e.to_string().starts_with("j.gltf: not valid glTF JSON"),
        "{e}"
    );
}

/// Garbled and truncated files are refused or read, never a panic: every prefix of a
/// GLB file, and copies with bytes changed at random (in the header, the JSON and the
/// buffer).
#[test]
fn garbled_files_never_panic() {
    let (doc, bin) = document(&[cube_prim()], json!({"translation": [1.0, 2.0, 3.0]}));
    let bytes = glb(&doc, &bin);
    let text = gltf_embedded(&doc, &bin);
    for cut in 0..bytes.len() {
        let _ = parse_gltf(&bytes[..cut], "cut.glb", None, Up::Z);
        let _ = parse_mesh(&bytes[..cut], "cut.glb");
    }
    for cut in (0..text.len()).step_by(7) {
        let _ = parse_gltf(&text[..cut], "cut.gltf", None, Up::Z);
    }
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let mut read = 0;
    for round in 0..3000 {
        let mut b = if round % 3 == 0 {
            text.clone()
        } else {
            bytes.clone()
        };
        for _ in 0..1 + next(4) {
            let at = next(b.len());
            b[at] = match next(3) {
                0 => next(256) as u8,
                1 => b"0123456789-e.,[]{}\""[next(19)],
                _ => b[at] ^ (1 << next(8)),
            };
        }
        read += usize::from(parse_gltf(&b, "garbled", None, Up::Z).is_ok());
    }
    // Changes in the buffer's coordinates still read; others are refused.
    assert!(read > 100 && read < 3000, "{read}");
}
