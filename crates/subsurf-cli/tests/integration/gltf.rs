//! `subsurf tessellate ... -o OUT.glb [--control-mesh]`: a valid GLB container whose
//! accessors hold the limit tessellation (triangles, unit normals, the `f32` of the PLY
//! output's `f64` positions) and, with `--control-mesh`, the input's edges as lines.

use crate::common;
use common::*;

use std::fs;

use serde_json::Value;
use subsurf::io::read_ply;

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// The JSON and BIN chunks of a GLB file, after checking the container.
fn chunks(bytes: &[u8]) -> (Value, &[u8]) {
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(u32_at(bytes, 4), 2, "version");
    assert_eq!(u32_at(bytes, 8) as usize, bytes.len(), "total length");
    let json_len = u32_at(bytes, 12) as usize;
    assert_eq!(&bytes[16..20], b"JSON");
    assert_eq!(json_len % 4, 0);
    let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("JSON chunk");
    let bin = &bytes[20 + json_len..];
    assert_eq!(u32_at(bin, 0) as usize, bin.len() - 8, "BIN chunk length");
    assert_eq!(&bin[4..8], b"BIN\0");
    (json, &bin[8..])
}

fn uint(v: &Value) -> usize {
    v.as_u64().expect("unsigned integer") as usize
}

/// Accessor `a`'s data: `u32` indices or `f32` components.
fn data<'b>(json: &Value, bin: &'b [u8], a: usize) -> &'b [u8] {
    let acc = &json["accessors"][a];
    let view = &json["bufferViews"][uint(&acc["bufferView"])];
    let start = uint(&view["byteOffset"]) + acc.get("byteOffset").map_or(0, uint);
    assert_eq!(start % 4, 0, "accessor {a} aligned");
    let size = uint(&acc["count"]) * if acc["type"] == "VEC3" { 12 } else { 4 };
    assert!(
        size <= uint(&view["byteLength"]),
        "accessor {a} fits its view"
    );
    &bin[start..start + size]
}

fn u32s(json: &Value, bin: &[u8], a: usize) -> Vec<u32> {
    assert_eq!(json["accessors"][a]["componentType"], 5125, "UNSIGNED_INT");
    data(json, bin, a)
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
        .collect()
}

fn vec3s(json: &Value, bin: &[u8], a: usize) -> Vec<[f32; 3]> {
    assert_eq!(json["accessors"][a]["componentType"], 5126, "FLOAT");
    data(json, bin, a)
        .chunks_exact(12)
        .map(|b| [0, 4, 8].map(|k| f32::from_le_bytes(b[k..k + 4].try_into().unwrap())))
        .collect()
}

/// Checks mesh `m`'s primitive (mode, index range, POSITION bounds, unit normals) and
/// returns its positions and indices.
fn primitive(json: &Value, bin: &[u8], m: usize, mode: u64) -> (Vec<[f32; 3]>, Vec<u32>) {
    let p = &json["meshes"][m]["primitives"][0];
    assert_eq!(p.get("mode").and_then(Value::as_u64).unwrap_or(4), mode);
    let pa = uint(&p["attributes"]["POSITION"]);
    let pos = vec3s(json, bin, pa);
    assert_eq!(pos.len(), uint(&json["accessors"][pa]["count"]));
    for k in 0..3 {
        let lo = pos.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
        let hi = pos.iter().map(|p| p[k]).fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(
            json["accessors"][pa]["min"][k].as_f64(),
            Some(f64::from(lo))
        );
        assert_eq!(
            json["accessors"][pa]["max"][k].as_f64(),
            Some(f64::from(hi))
        );
    }
    let idx = u32s(json, bin, uint(&p["indices"]));
    assert_eq!(idx.len() % if mode == 1 { 2 } else { 3 }, 0);
    assert!(
        idx.iter().all(|&i| (i as usize) < pos.len()),
        "index max < vertex count"
    );
    if let Some(n) = p["attributes"].get("NORMAL") {
        let normals = vec3s(json, bin, uint(n));
        assert_eq!(normals.len(), pos.len());
        for n in normals {
            let len = n.iter().map(|c| c * c).sum::<f32>().sqrt();
            assert!((len - 1.0).abs() < 1e-6, "{n:?}");
        }
    }
    (pos, idx)
}

#[test]
fn glb_with_control_mesh() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "cube.obj",
            "-o",
            "cube.glb",
            "--rate",
            "4",
            "--control-mesh",
        ],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("cube.glb")).unwrap();
    let (json, bin) = chunks(&bytes);
    assert_eq!(json["asset"]["version"], "2.0");
    assert_eq!(json["nodes"][0]["name"], "limit surface");
    assert_eq!(json["nodes"][1]["name"], "control mesh");
    assert_eq!(
        json["scenes"][uint(&json["scene"])]["nodes"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
    assert_eq!(json["accessors"].as_array().unwrap().len(), 5);

    let (pos, tris) = primitive(&json, bin, 0, 4);
    assert_eq!(pos.len(), 6 * 16 + 2);
    assert_eq!(tris.len(), 6 * 16 * 2 * 3);
    let (ctrl, lines) = primitive(&json, bin, 1, 1);
    assert_eq!(ctrl.len(), 8);
    assert_eq!(lines.len(), 12 * 2, "a cube has 12 edges");
    let mut edges: Vec<[u32; 2]> = lines
        .chunks_exact(2)
        .map(|l| [l[0].min(l[1]), l[0].max(l[1])])
        .collect();
    edges.sort();
    edges.dedup();
    assert_eq!(edges.len(), 12, "each edge once");

    // Same samples as the full-precision PLY output, turned from Z up to glTF's Y up
    // ((x, y, z) -> (x, z, -y)) and rounded to f32.
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "cube.obj",
            "-o",
            "cube.ply",
            "--rate",
            "4",
            "--triangles",
        ],
    );
    assert_code(&o, 0);
    let ply = read_ply(&fs::read(dir.path().join("cube.ply")).unwrap()).unwrap();
    assert_eq!(ply.positions.len(), pos.len());
    for (g, p) in pos.iter().zip(&ply.positions) {
        assert_eq!(*g, [p[0], p[2], -p[1]].map(|c| c as f32));
    }
    assert_eq!(ply.face_verts, tris, "the same triangles");
    let (ctrl, _) = primitive(&json, bin, 1, 1);
    for (g, p) in ctrl.iter().zip(positions(CUBE)) {
        assert_eq!(*g, [p[0], p[2], -p[1]].map(|c| c as f32));
    }
}

/// glTF is Y-up: `tessellate` turns a Z-up model (the default, `--up z`) so that its up
/// axis is +Y (the pawn stands along +Y, its normals turned with it); `--up y` keeps a
/// Y-up model as it is; `--up` with another output is refused.
#[test]
fn glb_is_y_up() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../subsurf/tests/shapes/osd/catmark_pawn.obj");
    let pawn = fs::read_to_string(path).unwrap();
    let dir = dir_with(&[("pawn.obj", &pawn)]);
    let tess = |out: &str, extra: &[&str]| {
        let mut args = vec!["tessellate", "pawn.obj", "-o", out, "--rate", "2"];
        args.extend_from_slice(extra);
        run_in(dir.path(), &args)
    };
    assert_code(&tess("pawn.ply", &["--triangles"]), 0);
    let ply = read_ply(&fs::read(dir.path().join("pawn.ply")).unwrap()).unwrap();
    let extent = |ps: &[[f64; 3]], k: usize| {
        let lo = ps.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
        let hi = ps.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
        hi - lo
    };
    assert!(
        extent(&ply.positions, 2) > 1.5 * extent(&ply.positions, 1),
        "Z-up"
    );
    for (up, extra) in [
        ("z", &[][..]),
        ("z", &["--up", "z"][..]),
        ("y", &["--up", "y"][..]),
    ] {
        assert_code(&tess("pawn.glb", extra), 0);
        let bytes = fs::read(dir.path().join("pawn.glb")).unwrap();
        let (json, bin) = chunks(&bytes);
        let (pos, _) = primitive(&json, bin, 0, 4);
        let p = json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].clone();
        let nrm = vec3s(&json, bin, uint(&p));
        let normals = ply.normals.as_ref().unwrap();
        for (i, q) in ply.positions.iter().enumerate() {
            let (turned, n) = match up {
                "z" => ([q[0], q[2], -q[1]], normals[i]),
                _ => (*q, normals[i]),
            };
            assert_eq!(pos[i], turned.map(|c| c as f32), "{extra:?} vertex {i}");
            let n = match up {
                "z" => [n[0], n[2], -n[1]],
                _ => n,
            };
            for k in 0..3 {
                assert!(
                    (f64::from(nrm[i][k]) - n[k]).abs() < 1e-6,
                    "{n:?} {:?}",
                    nrm[i]
                );
            }
        }
        let pos: Vec<[f64; 3]> = pos.iter().map(|p| p.map(f64::from)).collect();
        let tall = if up == "z" { 1 } else { 2 };
        assert!(
            extent(&pos, tall) > 1.5 * extent(&pos, 3 - tall),
            "{extra:?}"
        );
    }
    let o = tess("pawn-up.obj", &["--up", "y"]);
    assert_code(&o, 1);
    assert!(stderr(&o).contains("--up applies to a .glb output only"));
}

#[test]
fn glb_without_control_mesh_has_one_node() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "OUT.GLB", "--rate", "3"],
    );
    assert_code(&o, 0);
    let bytes = fs::read(dir.path().join("OUT.GLB")).unwrap();
    let (json, bin) = chunks(&bytes);
    assert_eq!(json["nodes"].as_array().unwrap().len(), 1);
    assert_eq!(json["meshes"].as_array().unwrap().len(), 1);
    let (pos, tris) = primitive(&json, bin, 0, 4);
    assert_eq!(pos.len(), 6 * 9 + 2);
    assert_eq!(tris.len(), 6 * 9 * 2 * 3);
}

#[test]
fn control_mesh_needs_glb() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &[
            "tessellate",
            "cube.obj",
            "-o",
            "cube.ply",
            "--rate",
            "2",
            "--control-mesh",
        ],
    );
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("--control-mesh needs a .glb"),
        "{}",
        stderr(&o)
    );
    assert_eq!(listing(dir.path()), ["cube.obj"]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "cube.gltf", "--rate", "2"],
    );
    assert_code(&o, 2);
    assert!(stderr(&o).contains(".glb"), "{}", stderr(&o));
}
