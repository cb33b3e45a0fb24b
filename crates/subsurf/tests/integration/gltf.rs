//! `io::gltf::write_glb`: the GLB container (header, chunk lengths and padding), what the
//! Khronos glTF validator checks that can be checked offline (accessor bounds and
//! alignment, buffer view lengths, index component types and ranges, exact `POSITION`
//! min/max, unit normals), the values written (`f32` of the `f64` input, fan
//! triangulation), and a read-back with the independent `gltf` crate (which validates the
//! JSON on load).

use serde_json::Value;
use subsurf::io::parse_obj;
use subsurf::io::Up;
use subsurf::io::{face_edges, to_gltf_frame, write_glb, GlbLines, GlbMesh, CHUNK_BIN, CHUNK_JSON};
use subsurf::limit::{tessellate_mesh, Tessellation};
use subsurf::mesh::{Options, PolyMesh};

fn shape(name: &str) -> (PolyMesh, Options) {
    let path = format!("{}/tests/shapes/osd/{name}.obj", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read(&path).expect("shape file");
    let f = parse_obj(&text[..], &path).expect("valid OBJ");
    (f.mesh, f.options.resolve(Options::default()))
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn f32_at(b: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// A GLB file taken apart, after checking its container and every accessor.
struct Glb {
    json: Value,
    bin: Vec<u8>,
}

impl Glb {
    /// Parses and checks `bytes` (panics on the first violation).
    fn parse(bytes: &[u8]) -> Self {
        assert!(bytes.len() >= 28, "too short: {}", bytes.len());
        assert_eq!(&bytes[0..4], b"glTF", "magic");
        assert_eq!(u32_at(bytes, 4), 2, "version");
        assert_eq!(u32_at(bytes, 8) as usize, bytes.len(), "header length");
        let json_len = u32_at(bytes, 12) as usize;
        assert_eq!(u32_at(bytes, 16), CHUNK_JSON);
        assert_eq!(json_len % 4, 0, "JSON chunk length is a multiple of 4");
        let text = &bytes[20..20 + json_len];
        let trimmed = text.trim_ascii_end();
        assert!(
            text[trimmed.len()..].iter().all(|&c| c == b' '),
            "JSON is padded with spaces"
        );
        assert!(text.len() - trimmed.len() < 4, "at most 3 bytes of padding");
        let json: Value = serde_json::from_slice(text).expect("JSON chunk parses");
        let at = 20 + json_len;
        let bin_len = u32_at(bytes, at) as usize;
        assert_eq!(u32_at(bytes, at + 4), CHUNK_BIN);
        assert_eq!(bin_len % 4, 0, "BIN chunk length is a multiple of 4");
        assert_eq!(at + 8 + bin_len, bytes.len(), "BIN is the last chunk");
        let bin = bytes[at + 8..].to_vec();
        let glb = Self { json, bin };
        glb.check();
        glb
    }

    fn count(&self, list: &str) -> usize {
        self.json[list].as_array().map_or(0, Vec::len)
    }

    fn uint(v: &Value) -> usize {
        v.as_u64().expect("a non-negative integer") as usize
    }

    /// The validator's structural checks.
    fn check(&self) {
        let j = &self.json;
        assert_eq!(j["asset"]["version"], "2.0");
        assert_eq!(self.count("buffers"), 1);
        let buffer = &j["buffers"][0];
        assert!(buffer.get("uri").is_none(), "the GLB buffer has no uri");
        let byte_length = Self::uint(&buffer["byteLength"]);
        assert!(byte_length <= self.bin.len() && self.bin.len() - byte_length < 4);
        for v in j["bufferViews"].as_array().unwrap() {
            assert_eq!(Self::uint(&v["buffer"]), 0);
            let (off, len) = (Self::uint(&v["byteOffset"]), Self::uint(&v["byteLength"]));
            assert!(
                len >= 1 && off + len <= byte_length,
                "view inside the buffer"
            );
            assert!(v.get("byteStride").is_none());
        }
        for (i, a) in j["accessors"].as_array().unwrap().iter().enumerate() {
            let view = &j["bufferViews"][Self::uint(&a["bufferView"])];
            let ct = Self::uint(&a["componentType"]);
            let size = match ct {
                5120 | 5121 => 1,
                5122 | 5123 => 2,
                5125 | 5126 => 4,
                _ => panic!("accessor {i}: componentType {ct}"),
            };
            let comps = match a["type"].as_str().unwrap() {
                "SCALAR" => 1,
                "VEC2" => 2,
                "VEC3" => 3,
                "VEC4" => 4,
                t => panic!("accessor {i}: type {t}"),
            };
            let offset = a.get("byteOffset").map_or(0, Self::uint);
            let start = Self::uint(&view["byteOffset"]) + offset;
            assert_eq!(offset % size, 0, "accessor {i}: byteOffset aligned");
            assert_eq!(start % size, 0, "accessor {i}: data aligned");
            assert_eq!(start % 4, 0, "accessor {i}: 4-byte aligned");
            let count = Self::uint(&a["count"]);
            assert!(count >= 1, "accessor {i}: count");
            assert!(
                offset + count * comps * size <= Self::uint(&view["byteLength"]),
                "accessor {i} fits its view"
            );
        }
        for (m, mesh) in j["meshes"].as_array().unwrap().iter().enumerate() {
            for p in mesh["primitives"].as_array().unwrap() {
                let mode = p.get("mode").map_or(4, Self::uint);
                let pos = Self::uint(&p["attributes"]["POSITION"]);
                let n = Self::uint(&j["accessors"][pos]["count"]);
                for (name, acc) in p["attributes"].as_object().unwrap() {
                    let acc = Self::uint(acc);
                    assert_eq!(
                        Self::uint(&j["accessors"][acc]["count"]),
                        n,
                        "mesh {m}: {name} has one value per vertex"
                    );
                    let view = Self::uint(&j["accessors"][acc]["bufferView"]);
                    assert_eq!(j["bufferViews"][view]["target"], 34962, "ARRAY_BUFFER");
                }
                let idx = Self::uint(&p["indices"]);
                let a = &j["accessors"][idx];
                assert_eq!(a["type"], "SCALAR");
                let ct = Self::uint(&a["componentType"]);
                assert!([5121, 5123, 5125].contains(&ct), "index componentType {ct}");
                let view = Self::uint(&a["bufferView"]);
                assert_eq!(j["bufferViews"][view]["target"], 34963, "ELEMENT_ARRAY");
                let indices = self.u32s(idx);
                let per = match mode {
                    1 => 2,
                    4 => 3,
                    _ => panic!("mode {mode}"),
                };
                assert_eq!(indices.len() % per, 0);
                assert!(
                    indices.iter().all(|&i| (i as usize) < n),
                    "index max < vertex count"
                );
                // POSITION: min/max present and exactly the bounds of the data.
                let values = self.vec3s(pos);
                for k in 0..3 {
                    let lo = values.iter().map(|v| v[k]).fold(f32::INFINITY, f32::min);
                    let hi = values
                        .iter()
                        .map(|v| v[k])
                        .fold(f32::NEG_INFINITY, f32::max);
                    assert_eq!(j["accessors"][pos]["min"][k].as_f64(), Some(f64::from(lo)));
                    assert_eq!(j["accessors"][pos]["max"][k].as_f64(), Some(f64::from(hi)));
                }
                if let Some(nrm) = p["attributes"].get("NORMAL") {
                    for v in self.vec3s(Self::uint(nrm)) {
                        let len = v.iter().map(|c| c * c).sum::<f32>().sqrt();
                        assert!((len - 1.0).abs() < 1e-6, "normal {v:?} is unit");
                    }
                }
            }
        }
        let scene = &j["scenes"][Self::uint(&j["scene"])];
        for n in scene["nodes"].as_array().unwrap() {
            assert!(Self::uint(n) < self.count("nodes"));
        }
    }

    fn data(&self, accessor: usize) -> &[u8] {
        let a = &self.json["accessors"][accessor];
        let v = &self.json["bufferViews"][Self::uint(&a["bufferView"])];
        let start = Self::uint(&v["byteOffset"]) + a.get("byteOffset").map_or(0, Self::uint);
        &self.bin[start..start + Self::uint(&v["byteLength"])]
    }

    fn u32s(&self, accessor: usize) -> Vec<u32> {
        assert_eq!(self.json["accessors"][accessor]["componentType"], 5125);
        let n = Self::uint(&self.json["accessors"][accessor]["count"]);
        let d = self.data(accessor);
        (0..n).map(|i| u32_at(d, 4 * i)).collect()
    }

    fn vec3s(&self, accessor: usize) -> Vec<[f32; 3]> {
        let a = &self.json["accessors"][accessor];
        assert_eq!(a["componentType"], 5126);
        assert_eq!(a["type"], "VEC3");
        let d = self.data(accessor);
        (0..Self::uint(&a["count"]))
            .map(|i| [0, 1, 2].map(|k| f32_at(d, 12 * i + 4 * k)))
            .collect()
    }

    /// The accessor of `semantic` (or of the indices, with `"indices"`) of mesh `m`.
    fn accessor(&self, m: usize, semantic: &str) -> Option<usize> {
        let p = &self.json["meshes"][m]["primitives"][0];
        let a = if semantic == "indices" {
            p.get("indices")
        } else {
            p["attributes"].get(semantic)
        };
        a.map(Self::uint)
    }
}

fn glb_bytes(mesh: &GlbMesh) -> Vec<u8> {
    let mut out = Vec::new();
    write_glb(&mut out, mesh).expect("write_glb");
    out
}

fn surface(t: &Tessellation) -> GlbMesh<'_> {
    GlbMesh {
        positions: &t.positions,
        normals: Some(&t.normals),
        face_offsets: &t.face_offsets,
        face_verts: &t.face_verts,
        ..Default::default()
    }
}

#[test]
fn tessellated_cube_with_control_mesh() {
    let (mesh, options) = shape("catmark_cube");
    let t = tessellate_mesh(&mesh, &options, 8, true).unwrap();
    let edges = face_edges(mesh.face_offsets(), mesh.face_verts());
    assert_eq!(edges.len(), 12);
    let bytes = glb_bytes(&GlbMesh {
        name: "cube",
        control: Some(GlbLines {
            positions: mesh.positions(),
            lines: &edges,
        }),
        ..surface(&t)
    });
    let g = Glb::parse(&bytes);
    let j = &g.json;
    assert_eq!(g.count("nodes"), 2);
    assert_eq!(g.count("meshes"), 2);
    assert_eq!(g.count("accessors"), 5);
    assert_eq!(j["nodes"][0]["name"], "cube");
    assert_eq!(j["nodes"][1]["name"], "control mesh");
    assert_eq!(j["scenes"][0]["nodes"], serde_json::json!([0, 1]));
    assert_eq!(j["meshes"][1]["primitives"][0]["mode"], 1, "LINES");
    assert!(j["asset"]["generator"]
        .as_str()
        .unwrap()
        .starts_with("subsurf "));

    // The values: f32 of the f64 input turned from Z up to glTF's Y up, (x, z, -y);
    // indices unchanged (the faces are triangles).
    let pos = g.vec3s(g.accessor(0, "POSITION").unwrap());
    assert_eq!(pos.len(), t.num_vertices());
    for (a, b) in pos.iter().zip(&t.positions) {
        assert_eq!(*a, [b[0], b[2], -b[1]].map(|c| c as f32));
    }
    let nrm = g.vec3s(g.accessor(0, "NORMAL").unwrap());
    for (a, b) in nrm.iter().zip(&t.normals) {
        let b = [b[0], b[2], -b[1]];
        for k in 0..3 {
            assert!((f64::from(a[k]) - b[k]).abs() < 1e-7, "{a:?} {b:?}");
        }
    }
    assert_eq!(g.u32s(g.accessor(0, "indices").unwrap()), t.face_verts);
    assert_eq!(g.u32s(g.accessor(1, "indices").unwrap()).len(), 24);
    let ctrl = g.vec3s(g.accessor(1, "POSITION").unwrap());
    assert_eq!(ctrl.len(), mesh.num_vertices());
    assert!(g.accessor(0, "COLOR_0").is_none());
}

#[test]
fn polygons_are_fans_and_colours_are_written() {
    // Quads, n-gons and a triangle, open boundary.
    let (mesh, options) = shape("catmark_nonquads");
    let t = tessellate_mesh(&mesh, &options, 2, false).unwrap();
    let colors: Vec<[f32; 3]> = t
        .positions
        .iter()
        .enumerate()
        .map(|(i, _)| [(i % 7) as f32 / 6.0, 0.5, 1.0])
        .collect();
    let bytes = glb_bytes(&GlbMesh {
        colors: Some(&colors),
        ..surface(&t)
    });
    let g = Glb::parse(&bytes);
    assert_eq!(g.count("nodes"), 1);
    assert_eq!(g.json["nodes"][0]["name"], "surface");
    assert_eq!(g.json["scenes"][0]["nodes"], serde_json::json!([0]));
    let idx = g.u32s(g.accessor(0, "indices").unwrap());
    let mut want = Vec::new();
    for f in 0..t.num_faces() {
        let fv = t.face(f);
        for k in 1..fv.len() - 1 {
            want.extend_from_slice(&[fv[0], fv[k], fv[k + 1]]);
        }
    }
    assert_eq!(idx, want);
    assert_eq!(g.vec3s(g.accessor(0, "COLOR_0").unwrap()), colors);
    // A vertex colour multiplies the base colour: white.
    assert_eq!(
        g.json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"],
        serde_json::json!([1.0, 1.0, 1.0, 1.0])
    );
}

#[test]
fn zero_and_long_normals_become_unit() {
    let p = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.1]];
    let n = [
        [0.0; 3],
        [0.0, 0.0, 3.0],
        [0.1, 0.2, 0.9],
        [1e-30, 0.0, 0.0],
    ];
    let bytes = glb_bytes(&GlbMesh {
        positions: &p,
        normals: Some(&n),
        face_offsets: &[0, 4],
        face_verts: &[0, 1, 3, 2],
        up: Up::Y,
        ..Default::default()
    });
    let g = Glb::parse(&bytes);
    let nrm = g.vec3s(g.accessor(0, "NORMAL").unwrap());
    assert_eq!(nrm[0], [0.0, 0.0, 1.0]);
    assert_eq!(nrm[1], [0.0, 0.0, 1.0]);
    assert_eq!(nrm[3], [1.0, 0.0, 0.0]);
    assert_eq!(
        g.u32s(g.accessor(0, "indices").unwrap()),
        [0, 1, 3, 0, 3, 2]
    );
    // The JSON chunk needed padding here or not; either way the container checks passed.
    assert_eq!(bytes.len() % 4, 0);
}

/// The independent reader: the `gltf` crate validates the document on load and reads
/// the buffers through its own accessor code.
#[test]
fn gltf_crate_reads_it_back() {
    let (mesh, options) = shape("catmark_pyramid_creases0");
    let t = tessellate_mesh(&mesh, &options, 4, true).unwrap();
    let edges = face_edges(mesh.face_offsets(), mesh.face_verts());
    let bytes = glb_bytes(&GlbMesh {
        control: Some(GlbLines {
            positions: mesh.positions(),
            lines: &edges,
        }),
        ..surface(&t)
    });
    let doc = gltf::Gltf::from_slice(&bytes).expect("gltf validates and loads the file");
    let blob = doc.blob.as_deref().expect("GLB has a BIN chunk");
    let scene = doc.default_scene().expect("a default scene");
    let meshes: Vec<gltf::Mesh> = scene.nodes().filter_map(|n| n.mesh()).collect();
    assert_eq!(meshes.len(), 2);

    let p = meshes[0].primitives().next().unwrap();
    assert_eq!(p.mode(), gltf::mesh::Mode::Triangles);
    let r = p.reader(|_| Some(blob));
    let pos: Vec<[f32; 3]> = r.read_positions().unwrap().collect();
    assert_eq!(pos.len(), t.num_vertices());
    let idx: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
    assert_eq!(idx, t.face_verts);
    assert_eq!(r.read_normals().unwrap().count(), t.num_vertices());
    let bb = p.bounding_box();
    let turned: Vec<[f64; 3]> = (t.positions.iter())
        .map(|&p| to_gltf_frame(p, Up::Z))
        .collect();
    for k in 0..3 {
        let lo = turned.iter().map(|p| p[k] as f32).fold(f32::MAX, f32::min);
        let hi = turned.iter().map(|p| p[k] as f32).fold(f32::MIN, f32::max);
        assert_eq!((bb.min[k], bb.max[k]), (lo, hi));
    }

    let l = meshes[1].primitives().next().unwrap();
    assert_eq!(l.mode(), gltf::mesh::Mode::Lines);
    let r = l.reader(|_| Some(blob));
    assert_eq!(r.read_positions().unwrap().count(), mesh.num_vertices());
    let lines: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
    assert_eq!(lines, edges.concat());
}

#[test]
fn empty_control_mesh_is_left_out() {
    let (mesh, options) = shape("catmark_cube");
    let t = tessellate_mesh(&mesh, &options, 1, true).unwrap();
    let bytes = glb_bytes(&GlbMesh {
        control: Some(GlbLines {
            positions: mesh.positions(),
            lines: &[],
        }),
        ..surface(&t)
    });
    let g = Glb::parse(&bytes);
    assert_eq!(g.count("nodes"), 1);
    assert_eq!(g.count("meshes"), 1);
}

/// glTF is Y-up: a Z-up model (OpenSubdiv's pawn stands along +Z) is written standing
/// along +Y, read back with the `gltf` crate: each position and normal turned by
/// (x, y, z) -> (x, z, -y), the pawn's height along Y, its top at the largest Y with its
/// normal pointing up, the faces still wound outward. With `Up::Y` the values are kept.
#[test]
fn z_up_models_stand_along_y() {
    let (mesh, options) = shape("catmark_pawn");
    let t = tessellate_mesh(&mesh, &options, 4, true).unwrap();
    let extent = |ps: &[[f64; 3]], k: usize| {
        let (lo, hi) = ps.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
            (lo.min(p[k]), hi.max(p[k]))
        });
        hi - lo
    };
    // The pawn stands along Z: its height is its largest extent.
    assert!(extent(&t.positions, 2) > 1.5 * extent(&t.positions, 1));

    let read = |up: Up| {
        let bytes = glb_bytes(&GlbMesh { up, ..surface(&t) });
        let doc = gltf::Gltf::from_slice(&bytes).expect("gltf validates and loads the file");
        let blob = doc.blob.as_deref().expect("GLB has a BIN chunk").to_vec();
        let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
        let r = prim.reader(|_| Some(&blob[..]));
        let pos: Vec<[f64; 3]> = (r.read_positions().unwrap())
            .map(|p| p.map(f64::from))
            .collect();
        let nrm: Vec<[f64; 3]> = (r.read_normals().unwrap())
            .map(|n| n.map(f64::from))
            .collect();
        let idx: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
        (pos, nrm, idx)
    };
    let (pos, nrm, idx) = read(Up::Z);
    assert_eq!(idx, t.face_verts, "the same triangles, in the same order");
    for (i, (g, p)) in pos.iter().zip(&t.positions).enumerate() {
        assert_eq!(
            *g,
            [p[0], p[2], -p[1]].map(|c| f64::from(c as f32)),
            "vertex {i}"
        );
    }
    // Height along Y now, and as tall as the model was along Z.
    let h = extent(&pos, 1);
    assert!((h - extent(&t.positions, 2)).abs() < 1e-5 * h);
    assert!(h > 1.5 * extent(&pos, 2));
    // The top: the highest vertex, whose normal points up (+Y).
    let top = (0..pos.len())
        .max_by(|&a, &b| pos[a][1].total_cmp(&pos[b][1]))
        .unwrap();
    assert!(nrm[top][1] > 0.99, "normal at the top: {:?}", nrm[top]);
    // Each triangle's winding agrees with its vertices' normals (outward), as before.
    let mut agree = 0;
    for tri in idx.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| pos[tri[k] as usize]);
        let (u, v) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let m = nrm[tri[0] as usize];
        agree += usize::from(n[0] * m[0] + n[1] * m[1] + n[2] * m[2] > 0.0);
    }
    assert!(
        agree * 100 > 99 * (idx.len() / 3),
        "{agree} of {}",
        idx.len() / 3
    );

    let (pos, nrm, _) = read(Up::Y);
    for (g, p) in pos.iter().zip(&t.positions) {
        assert_eq!(*g, p.map(|c| f64::from(c as f32)));
    }
    for (g, n) in nrm.iter().zip(&t.normals) {
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        for k in 0..3 {
            assert!((g[k] - n[k] / len).abs() < 1e-6);
        }
    }
}
