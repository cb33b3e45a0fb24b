//! How every command reads its mesh: OBJ or PLY (ASCII, binary little- and big-endian),
//! told apart by content, the same results from each; other formats refused with a
//! message naming the formats read; input read in blocks (a stream of anything but text
//! stops after its first block; the bytes given to the process are counted, no timing)
//! and counted against `--max-memory`; errors on standard input name `<stdin>`.

use crate::common;
use common::*;

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// The vertices and faces (0-based) of an OBJ text with `v` and `f` lines (positive
/// indices).
fn mesh_of(obj: &str) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let faces = obj
        .lines()
        .filter_map(|l| l.strip_prefix("f "))
        .map(|rest| {
            let f = rest.split_whitespace();
            // `v`, `v/vt`, ...: the vertex.
            f.map(|t| t.split('/').next().unwrap().parse::<u32>().expect("index") - 1)
                .collect()
        })
        .collect();
    (positions(obj), faces)
}

/// The mesh as PLY: `format` is `ascii`, `binary_little_endian` or `binary_big_endian`;
/// double coordinates, `uchar int vertex_indices`.
pub fn ply(obj: &str, format: &str) -> Vec<u8> {
    let (p, faces) = mesh_of(obj);
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
         property double z\nelement face {}\nproperty list uchar int vertex_indices\n\
         end_header\n",
        p.len(),
        faces.len()
    )
    .into_bytes();
    let big = format == "binary_big_endian";
    let number = |out: &mut Vec<u8>, b: &[u8]| match big {
        true => out.extend(b.iter().rev()),
        false => out.extend_from_slice(b),
    };
    for q in &p {
        match format {
            "ascii" => out.extend_from_slice(format!("{} {} {}\n", q[0], q[1], q[2]).as_bytes()),
            _ => q.iter().for_each(|c| number(&mut out, &c.to_le_bytes())),
        }
    }
    for f in &faces {
        if format == "ascii" {
            let words: Vec<String> = f.iter().map(u32::to_string).collect();
            out.extend_from_slice(format!("{} {}\n", f.len(), words.join(" ")).as_bytes());
        } else {
            out.push(f.len() as u8);
            f.iter()
                .for_each(|&i| number(&mut out, &(i as i32).to_le_bytes()));
        }
    }
    out
}

/// OpenSubdiv's pawn: its vertices and faces, without its tags and texture coordinates
/// (which PLY does not hold).
fn pawn() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../subsurf/tests/shapes/osd");
    let text = fs::read_to_string(path.join("catmark_pawn.obj")).expect("pawn");
    let (p, faces) = mesh_of(&text);
    let mut obj = String::new();
    for q in p {
        obj += &format!("v {} {} {}\n", q[0], q[1], q[2]);
    }
    for f in faces {
        let words: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        obj += &format!("f {}\n", words.join(" "));
    }
    obj
}

const FORMATS: [&str; 3] = ["ascii", "binary_little_endian", "binary_big_endian"];

/// stdout without the lines that name the input (`file:` of `info`, `"file"` of its
/// JSON, the comment lines of written OBJ files).
fn without_names(out: &[u8]) -> String {
    String::from_utf8_lossy(out)
        .lines()
        .filter(|l| {
            !(l.starts_with("file:")
                || l.trim_start().starts_with("\"file\"")
                || l.starts_with('#'))
        })
        .map(|l| format!("{l}\n"))
        .collect()
}

/// The same mesh as OBJ and as PLY in each encoding (and named .obj, and on standard
/// input) gives the same `info`, `info --json`, `subdivide` and `limit` output.
#[test]
fn ply_reads_as_the_obj() {
    for (name, obj) in [("hut", HUT.to_owned()), ("pawn", pawn())] {
        let dir = dir_with(&[("m.obj", &obj)]);
        for f in FORMATS {
            fs::write(dir.path().join(format!("{f}.ply")), ply(&obj, f)).unwrap();
        }
        fs::write(dir.path().join("named.obj"), ply(&obj, "binary_big_endian")).unwrap();
        let commands: [&[&str]; 4] = [
            &["info"],
            &["info", "--json"],
            &["subdivide", "-l", "2", "-o", "-"],
            &["limit", "--grid", "2", "-o", "-"],
        ];
        for args in commands {
            let run = |input: &str| {
                let mut a = vec![args[0], input];
                a.extend_from_slice(&args[1..]);
                let o = run_in(dir.path(), &a);
                assert_code(&o, 0);
                assert!(stderr(&o).is_empty(), "{a:?}: {}", stderr(&o));
                without_names(&o.stdout)
            };
            let want = run("m.obj");
            assert!(want.len() > 100, "{name} {args:?}");
            for input in [
                "ascii.ply",
                "binary_little_endian.ply",
                "binary_big_endian.ply",
            ] {
                assert_eq!(run(input), want, "{name} {input} {args:?}");
            }
            assert_eq!(run("named.obj"), want, "{name}: PLY named .obj, {args:?}");
        }
        let mut a = vec!["subdivide", "-", "-o", "-", "-l", "1"];
        let o = run_with_bytes(dir.path(), &a, &ply(&obj, "binary_little_endian"));
        assert_code(&o, 0);
        a[1] = "m.obj";
        assert_eq!(
            without_names(&o.stdout),
            without_names(&run_in(dir.path(), &a).stdout)
        );
    }
}

/// Every command that reads a polygon mesh reads PLY as it reads OBJ: the same output
/// (`repose` with a PLY base and a PLY pose).
#[test]
fn every_mesh_command_reads_ply() {
    let dir = dir_with(&[("m.obj", HUT)]);
    fs::write(dir.path().join("m.ply"), ply(HUT, "binary_little_endian")).unwrap();
    fs::create_dir(dir.path().join("out-obj")).unwrap();
    fs::create_dir(dir.path().join("out-ply")).unwrap();
    let commands: [&[&str]; 9] = [
        &["subdivide", "IN", "-o", "-", "-l", "1"],
        &["tessellate", "IN", "-o", "-", "--rate", "2"],
        &["render", "IN", "-o", "-", "--size", "40x30"],
        &["spline", "IN", "-o", "-", "--rate", "2"],
        &["regularity", "IN", "--sample", "3"],
        &["g2", "IN", "-o", "-", "--rate", "2"],
        &["bench", "IN", "-l", "1", "--reps", "1"],
        &["limit", "IN", "--grid", "2", "-o", "-"],
        &["info", "IN"],
    ];
    for args in commands {
        let outputs: Vec<(Option<i32>, String)> = ["m.obj", "m.ply"]
            .iter()
            .map(|input| {
                let a: Vec<&str> = args
                    .iter()
                    .map(|&s| if s == "IN" { input } else { s })
                    .collect();
                let o = run_in(dir.path(), &a);
                assert!(!stderr(&o).contains("panicked"), "{a:?}: {}", stderr(&o));
                (
                    o.status.code(),
                    without_names(&o.stdout).replace(input, "IN"),
                )
            })
            .collect();
        assert_eq!(outputs[0].0, outputs[1].0, "{args:?}");
        // `bench` prints timings; the others the same bytes.
        if args[0] != "bench" {
            assert_eq!(outputs[0].1, outputs[1].1, "{args:?}");
        }
    }
    for (base, out) in [("m.obj", "out-obj"), ("m.ply", "out-ply")] {
        let o = run_in(dir.path(), &["repose", base, base, "-o", out, "-l", "1"]);
        assert_code(&o, 0);
    }
    let written = |p: &str| without_names(&fs::read(dir.path().join(p)).unwrap());
    // PLY poses are written as OBJ, under the name with .obj.
    assert_eq!(written("out-obj/m.obj"), written("out-ply/m.obj"));
}

/// Files of other formats are refused with a message that names the formats read: a
/// binary STL (which `tessellate` writes), by its name; an ASCII STL by its content, on
/// standard input.
#[test]
fn other_formats_are_named() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    let o = run_in(
        dir.path(),
        &["tessellate", "cube.obj", "-o", "cube.stl", "--rate", "2"],
    );
    assert_code(&o, 0);
    let read = "meshes are read from OBJ, PLY and glTF (.gltf, .glb) files only";
    for file in ["cube.stl"] {
        for command in ["info", "subdivide"] {
            let mut args = vec![command, file];
            if command == "subdivide" {
                args.extend(["-o", "out.obj"]);
            }
            let o = run_in(dir.path(), &args);
            assert_code(&o, 1);
            let e = stderr(&o);
            assert!(
                e.starts_with(&format!(
                    "error: {file}: this looks like an STL file; {read}"
                )),
                "{e}"
            );
        }
    }
    let o = run_with_bytes(
        dir.path(),
        &["info", "-"],
        b"solid cube\nfacet normal 0 0 1\n",
    );
    assert_code(&o, 1);
    assert!(stderr(&o).starts_with("error: <stdin>: this looks like an STL file"));
    assert!(!listing(dir.path()).contains(&"out.obj".to_owned()));
}

/// A textured cube in binary glTF as exporters write it: 24 vertices (every face corner
/// its own), 12 triangles, each face's texture a square of its own, `v` down.
fn textured_cube_glb() -> Vec<u8> {
    let p = [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let faces = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let mut bin = Vec::new();
    for f in &faces {
        for &v in f {
            bin.extend(p[v].iter().flat_map(|x| x.to_le_bytes()));
        }
    }
    let uv_at = bin.len();
    for (i, _) in faces.iter().enumerate() {
        let (u0, v0) = ((i % 3) as f32 / 3.0, (i / 3) as f32 / 2.0);
        for (du, dv) in [(0.0, 0.5), (1.0 / 3.0, 0.5), (1.0 / 3.0, 0.0), (0.0, 0.0)] {
            bin.extend([u0 + du, v0 + dv].iter().flat_map(|x| x.to_le_bytes()));
        }
    }
    let idx_at = bin.len();
    for f in 0..6u32 {
        for k in [0, 1, 2, 0, 2, 3] {
            bin.extend((4 * f + k).to_le_bytes());
        }
    }
    let doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2}]}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 24, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 24, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 36, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": uv_at},
            {"buffer": 0, "byteOffset": uv_at, "byteLength": idx_at - uv_at},
            {"buffer": 0, "byteOffset": idx_at, "byteLength": bin.len() - idx_at},
        ],
        "buffers": [{"byteLength": bin.len()}],
    });
    let mut json = serde_json::to_vec(&doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut out = b"glTF".to_vec();
    let total = 12 + 8 + json.len() + 8 + bin.len();
    for w in [2u32, total as u32, json.len() as u32, 0x4E4F_534A] {
        out.extend(w.to_le_bytes());
    }
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(0x004E_4942u32.to_le_bytes());
    out.extend(&bin);
    out
}

/// glTF is read: a textured cube subdivides into an OBJ with its texture coordinates
/// (`vt`, faces `v/vt`), welded into the closed cube (Catmull-Clark level 1 of 12
/// triangles: 8 + 12 + 18 vertices, 36 quads); what the file holds besides is noted; a
/// glTF written by `tessellate` reads back as the tessellation (its positions rounded to
/// single precision, turned back to Z up).
#[test]
fn gltf_is_read() {
    let dir = dir_with(&[("cube.obj", CUBE)]);
    fs::write(dir.path().join("cube.glb"), textured_cube_glb()).unwrap();
    let o = run_in(
        dir.path(),
        &["subdivide", "cube.glb", "-l", "1", "-o", "out.obj"],
    );
    assert_code(&o, 0);
    let out = fs::read_to_string(dir.path().join("out.obj")).unwrap();
    let count = |kw: &str| out.lines().filter(|l| l.starts_with(kw)).count();
    assert_eq!((count("v "), count("f ")), (38, 36));
    assert!(count("vt ") > 38, "seams split the values");
    assert!(out
        .lines()
        .filter(|l| l.starts_with("f "))
        .all(|l| l.split(' ').skip(1).all(|c| c.contains('/'))));
    assert!(!stderr(&o).contains("ignored"), "{}", stderr(&o));
    for out in ["t.obj", "t.glb"] {
        let o = run_in(
            dir.path(),
            &["tessellate", "cube.obj", "-o", out, "--rate", "3"],
        );
        assert_code(&o, 0);
    }
    let o = run_in(
        dir.path(),
        &["subdivide", "t.glb", "-l", "0", "-o", "back.obj"],
    );
    assert_code(&o, 0);
    assert!(stderr(&o).contains("normals (NORMAL)"), "{}", stderr(&o));
    let single = |p: [f64; 3]| p.map(|x| (x as f32).to_bits());
    let mut written: Vec<_> = positions(&fs::read_to_string(dir.path().join("t.obj")).unwrap())
        .into_iter()
        .map(single)
        .collect();
    let mut back: Vec<_> = positions(&fs::read_to_string(dir.path().join("back.obj")).unwrap())
        .into_iter()
        .map(|p| p.map(|x| (x as f32).to_bits()))
        .collect();
    written.sort_unstable();
    back.sort_unstable();
    assert_eq!(written, back);
}

/// Every command that reads a mesh names `<stdin>` in its errors about standard input:
/// a malformed line, no faces, a file of another format.
#[test]
fn errors_on_standard_input_name_stdin() {
    let dir = tempfile::tempdir().unwrap();
    let commands: [&[&str]; 10] = [
        &["info", "-"],
        &["subdivide", "-", "-o", "-"],
        &["limit", "-", "-o", "-"],
        &["tessellate", "-", "-o", "-", "--rate", "2"],
        &["render", "-", "-o", "-"],
        &["bench", "-", "-l", "1"],
        &["spline", "-", "-o", "-"],
        &["regularity", "-"],
        &["g2", "-", "-o", "-"],
        &["repose", "-", "pose.obj", "-o", "."],
    ];
    let cases: [(&[u8], &str); 3] = [
        (
            b"v 0 0 0\nv 1 x 0\n",
            "error: <stdin>:2: v: 'x' is not a number",
        ),
        (b"v 0 0 0\n", "error: <stdin>: no faces"),
        (b"solid x\n", "error: <stdin>: this looks like an STL file"),
    ];
    for args in commands {
        for (input, message) in cases {
            if args[0] == "info" && message.contains("no faces") {
                continue;
            }
            let o = run_with_bytes(dir.path(), args, input);
            assert_code(&o, 1);
            assert!(stderr(&o).starts_with(message), "{args:?}: {}", stderr(&o));
            assert!(o.stdout.is_empty(), "{args:?}");
        }
    }
    assert!(listing(dir.path()).is_empty());
}

/// Runs `subsurf args` with `chunk` repeated without end on standard input (after
/// `head`), until the process exits; returns its output and how many bytes it took.
fn run_endless(args: &[&str], head: &[u8], chunk: &[u8]) -> (std::process::Output, u64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_subsurf"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot run subsurf");
    let mut stdin = child.stdin.take().expect("piped stdin");
    let given = Arc::new(AtomicU64::new(0));
    let counter = given.clone();
    let (head, block) = (head.to_vec(), chunk.repeat((1 << 16) / chunk.len()));
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(&head);
        counter.fetch_add(head.len() as u64, Ordering::Relaxed);
        // Until the process exits and the pipe breaks.
        while stdin.write_all(&block).is_ok() {
            counter.fetch_add(block.len() as u64, Ordering::Relaxed);
        }
    });
    let out = child.wait_with_output().expect("wait for subsurf");
    feeder.join().unwrap();
    (out, given.load(Ordering::Relaxed))
}

/// An endless stream of NUL bytes (3 GB of them took 2.8 GiB before line 1 was
/// reported) is refused at line 1 after a few MiB at most (a block and the pipe's
/// buffer); an endless stream of valid lines once it passes `--max-memory`.
#[test]
fn endless_input_stops_early() {
    let bound = 8 << 20;
    for command in ["info", "subdivide"] {
        let args = match command {
            "info" => vec!["info", "-"],
            _ => vec!["subdivide", "-", "-o", "-", "--max-memory", "200M"],
        };
        let (o, given) = run_endless(&args, b"", b"\0");
        assert_code(&o, 1);
        assert!(
            stderr(&o).starts_with(
                "error: <stdin>:1: line 1 contains the control character 0x00 (is this a \
                 binary file?)"
            ),
            "{}",
            stderr(&o)
        );
        assert!(given < bound, "{command} took {given} bytes");
    }
    let (o, given) = run_endless(
        &["info", "-", "--max-memory", "2M"],
        b"v 0 0 0\nv 1 0 0\n",
        b"\xff\xfe",
    );
    assert_code(&o, 1);
    assert!(stderr(&o).starts_with("error: <stdin>:3: line 3 is not valid UTF-8"));
    assert!(given < bound, "took {given} bytes");
    let (o, given) = run_endless(&["info", "-", "--max-memory", "2M"], b"", b"v 0 0 0\n");
    assert_code(&o, 1);
    assert!(
        stderr(&o).starts_with(
            "error: <stdin>: reading the mesh needs at least 3 MiB, more than the limit of \
             2 MiB (--max-memory); raise --max-memory"
        ),
        "{}",
        stderr(&o)
    );
    assert!(given < bound, "took {given} bytes");
    if Path::new("/dev/zero").exists() {
        let o = run_in(
            Path::new("/"),
            &["subdivide", "/dev/zero", "-o", "-", "--max-memory", "200M"],
        );
        assert_code(&o, 1);
        assert!(stderr(&o).starts_with("error: /dev/zero:1: line 1 contains the control"));
    }
}

/// `info` and the other commands count the input and the mesh parsed from it against
/// `--max-memory`: a file whose bytes fit but not with the vertices read from them is
/// refused before they are built, naming the file; with a higher limit it is read.
#[test]
fn input_counts_against_max_memory() {
    let text = "v 0 0 0\n".repeat(75_000) + "f 1 2 3\n";
    let dir = dir_with(&[("v.obj", &text)]);
    for args in [
        vec!["info", "v.obj", "--max-memory", "1M"],
        vec!["subdivide", "v.obj", "-o", "out.obj", "--max-memory", "1M"],
        vec!["info", "v.obj", "--max-memory", "300K"],
    ] {
        let o = run_in(dir.path(), &args);
        assert_code(&o, 1);
        let e = stderr(&o);
        let size = match args[args.len() - 1] {
            "1M" => "about 5 MiB",
            _ => "at least 586 KiB",
        };
        assert!(
            e.starts_with(&format!(
                "error: v.obj: reading the mesh needs {size}, more than"
            )),
            "{e}"
        );
    }
    let o = run_in(dir.path(), &["info", "v.obj", "--max-memory", "8M"]);
    assert_code(&o, 0);
    assert_eq!(listing(dir.path()), ["v.obj"]);
}

/// Old Mac OS files (lines ended by CR only) read as their LF twins, with the same line
/// numbers in messages.
#[test]
fn cr_line_ends_read_as_lf() {
    let cr = CUBE.replace('\n', "\r");
    let dir = dir_with(&[("lf.obj", CUBE), ("cr.obj", &cr)]);
    let a = run_in(dir.path(), &["subdivide", "lf.obj", "-o", "-", "-l", "2"]);
    let b = run_in(dir.path(), &["subdivide", "cr.obj", "-o", "-", "-l", "2"]);
    assert_code(&b, 0);
    assert_eq!(without_names(&a.stdout), without_names(&b.stdout));
    let bad = "v 0 0 0\rv 1 0 0\rv 1 1 0\rf 1 2 3 7\r";
    let o = run_with_bytes(dir.path(), &["info", "-"], bad.as_bytes());
    assert_code(&o, 1);
    assert!(stderr(&o).starts_with("error: <stdin>:4: f: vertex index 7 is out of range"));
}

/// Warnings about a PLY file's faces and vertices count them from 0, as the file does.
#[test]
fn ply_messages_count_from_zero() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 2 3\n";
    let dir = dir_with(&[("m.obj", obj)]);
    fs::write(dir.path().join("m.ply"), ply(obj, "ascii")).unwrap();
    let o = run_in(dir.path(), &["info", "m.obj", "--strict"]);
    assert!(stderr(&o).contains("m.obj:6: face 2 lists vertex 2 more than once"));
    let o = run_in(dir.path(), &["info", "m.ply", "--strict"]);
    assert_code(&o, 1);
    assert!(
        stderr(&o).contains("m.ply:15: face 1 lists vertex 1 more than once"),
        "{}",
        stderr(&o)
    );
}

/// OBJ objects, groups and materials reach the refined OBJ of `subdivide` and of
/// `repose`: `mtllib` first, each child face under its parent's `usemtl` (16 children per
/// quad at level 2); smoothing groups are noted as not kept.
#[test]
fn obj_groups_and_materials_are_kept() {
    let base = "mtllib cube.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                o cube\ng sides\nusemtl red\ns 1\nf 1 4 3 2\nf 5 6 7 8\nusemtl blue\nf 1 2 6 5\nf 2 3 7 6\n\
                f 3 4 8 7\nf 4 1 5 8\n";
    let dir = dir_with(&[("m.obj", base)]);
    let o = run_in(
        dir.path(),
        &["subdivide", "m.obj", "-l", "2", "-o", "out.obj"],
    );
    assert_code(&o, 0);
    assert!(
        stderr(&o).contains("smoothing-group statement(s) (s)"),
        "{}",
        stderr(&o)
    );
    let o = run_in(
        dir.path(),
        &["repose", "m.obj", "m.obj", "-o", "poses", "-l", "2"],
    );
    assert_code(&o, 0);
    for out in ["out.obj", "poses/m.obj"] {
        let text = fs::read_to_string(dir.path().join(out)).unwrap();
        let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(lines[0], "mtllib cube.mtl", "{out}");
        let mut material = "";
        let mut counts = std::collections::BTreeMap::new();
        for l in &lines {
            if let Some(m) = l.strip_prefix("usemtl ") {
                material = m;
            } else if l.starts_with("f ") {
                *counts.entry(material).or_insert(0) += 1;
            }
        }
        assert_eq!(
            counts,
            [("blue", 64), ("red", 32)].into_iter().collect(),
            "{out}"
        );
        for (kw, n) in [("o cube", 1), ("g sides", 1), ("usemtl ", 2)] {
            assert_eq!(
                lines.iter().filter(|l| l.starts_with(kw)).count(),
                n,
                "{out} {kw}"
            );
        }
    }
}
