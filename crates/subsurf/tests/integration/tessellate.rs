//! `limit::tessellate` as specifications: watertight (closed inputs give closed
//! 2-manifolds, open inputs keep their boundary loops), no cracked seams, unit normals,
//! exact samples of the B-spline surface on a regular torus; and the PLY and STL writers
//! on its output.
#![allow(clippy::needless_range_loop)]

use std::collections::HashMap;

use subsurf::io::{parse_obj, write_obj, WriteOptions};
use subsurf::io::{read_ply, write_ply};
use subsurf::io::{read_stl, write_stl};
use subsurf::limit::{bspline, tessellate, tessellate_mesh, LimitSurface, Tessellation};
use subsurf::mesh::{
    BoundaryInterpolation, Crease, Options, PolyMesh, Tags, Topology, SHARPNESS_INFINITE,
};

fn obj(text: &str) -> (PolyMesh, Options) {
    let f = parse_obj(text.as_bytes(), "test.obj").expect("valid OBJ");
    (f.mesh, f.options.resolve(Options::default()))
}

fn cube() -> (PolyMesh, Options) {
    obj(include_str!("../../../../examples/meshes/cube.obj"))
}

/// A regular `n × m` torus: vertex `(i, j)` is `i * m + j`; face `(i, j)` is
/// `[(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]`, so `u` runs along `i`, `v` along `j`.
fn torus(n: usize, m: usize) -> PolyMesh {
    let mut p = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b) = (
                std::f64::consts::TAU * i as f64 / n as f64,
                std::f64::consts::TAU * j as f64 / m as f64,
            );
            let r = 1.0 + 0.4 * b.cos() + 0.05 * ((3 * i + j) as f64).sin();
            p.push([r * a.cos(), r * a.sin(), 0.4 * b.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
    let faces: Vec<[u32; 4]> = (0..n)
        .flat_map(|i| (0..m).map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
        .collect();
    PolyMesh::from_faces(p, &faces).unwrap()
}

/// A cube whose top is split into a triangle, a quad and a pentagon (closed).
fn mixed() -> PolyMesh {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 1.0, 1.1],
    ];
    let f: Vec<Vec<u32>> = vec![
        vec![0, 3, 2, 1],
        vec![4, 5, 6],
        vec![4, 6, 8, 7],
        vec![0, 1, 5, 4],
        vec![1, 2, 6, 5],
        vec![2, 3, 7, 8, 6],
        vec![3, 0, 4, 7],
    ];
    PolyMesh::from_faces(p, &f).unwrap()
}

/// The cube with infinitely sharp creases around its top face and a semi-sharp one below.
fn creased_cube() -> (PolyMesh, Options) {
    let (mut m, o) = cube();
    let top = [4u32, 5, 6, 7];
    m.tags = Tags {
        creases: (0..4)
            .map(|i| Crease {
                v0: top[i],
                v1: top[(i + 1) % 4],
                sharpness: SHARPNESS_INFINITE,
            })
            .chain([Crease {
                v0: 0,
                v1: 1,
                sharpness: 1.5,
            }])
            .collect(),
        ..Tags::default()
    };
    (m, o)
}

/// Every test mesh: name, mesh, options, whether it is closed.
fn meshes() -> Vec<(&'static str, PolyMesh, Options, bool)> {
    let d = Options::default();
    let (c, co) = cube();
    let (g, go) = obj(include_str!("../../../../examples/meshes/grid.obj"));
    let (h, ho) = obj(include_str!("../../../../examples/meshes/hut.obj"));
    let (cc, cco) = obj(include_str!("../../../../examples/meshes/cube-crease.obj"));
    let (k, ko) = creased_cube();
    let mut holed = c.clone();
    holed.tags.holes = vec![1];
    vec![
        ("cube", c, co, true),
        ("torus", torus(8, 6), d, true),
        ("grid", g.clone(), go, false),
        (
            "grid-edge-only",
            g,
            Options {
                boundary: BoundaryInterpolation::EdgeOnly,
                ..d
            },
            false,
        ),
        ("mixed", mixed(), d, true),
        ("hut", h, ho, true),
        ("cube-crease", cc, cco, true),
        ("creased-cube", k, ko, true),
        ("cube-with-hole", holed, co, false),
    ]
}

/// How many times each edge (a vertex pair) occurs.
type EdgeCounts = HashMap<(u32, u32), usize>;

/// Undirected edge → number of output faces, and directed edge → count.
fn edge_counts(t: &Tessellation) -> (EdgeCounts, EdgeCounts) {
    let mut undirected = HashMap::new();
    let mut directed = HashMap::new();
    for f in 0..t.num_faces() {
        let fv = t.face(f);
        for i in 0..fv.len() {
            let (a, b) = (fv[i], fv[(i + 1) % fv.len()]);
            *undirected.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            *directed.entry((a, b)).or_insert(0) += 1;
        }
    }
    (undirected, directed)
}

/// Lengths of the boundary loops (directed boundary edges chained), sorted.
fn loop_lengths(next: &HashMap<u32, u32>) -> Vec<usize> {
    let mut seen = std::collections::HashSet::new();
    let mut lengths = Vec::new();
    for &start in next.keys() {
        if seen.contains(&start) {
            continue;
        }
        let mut len = 0;
        let mut v = start;
        while seen.insert(v) {
            len += 1;
            v = next[&v];
        }
        assert_eq!(v, start, "boundary does not close into a loop");
        lengths.push(len);
    }
    lengths.sort_unstable();
    lengths
}

fn output_boundary_loops(t: &Tessellation) -> Vec<usize> {
    let (undirected, directed) = edge_counts(t);
    let next: HashMap<u32, u32> = directed
        .keys()
        .filter(|&&(a, b)| undirected[&(a.min(b), a.max(b))] == 1)
        .map(|&(a, b)| (a, b))
        .collect();
    loop_lengths(&next)
}

/// Boundary loops of the input's faces with a surface.
fn input_boundary_loops(mesh: &PolyMesh, options: &Options) -> Vec<usize> {
    let s = LimitSurface::new(mesh, *options).unwrap();
    let (t, _) = Topology::from_mesh(mesh, options).unwrap();
    let mut next = HashMap::new();
    for e in 0..t.num_edges() {
        let live: Vec<u32> = t
            .edge_face_list(e)
            .iter()
            .copied()
            .filter(|&f| s.has_surface(f as usize))
            .collect();
        if live.len() == 1 {
            let f = live[0] as usize;
            let fv = t.face_vertices(f);
            let i = t
                .face_edge_list(f)
                .iter()
                .position(|&x| x as usize == e)
                .unwrap();
            next.insert(fv[i], fv[(i + 1) % fv.len()]);
        }
    }
    loop_lengths(&next)
}

/// No two distinct vertices within `tol` of each other.
fn assert_no_duplicates(name: &str, p: &[[f64; 3]], tol: f64) {
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by(|&a, &b| p[a][0].total_cmp(&p[b][0]));
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if p[b][0] - p[a][0] > tol {
                break;
            }
            let d = (0..3)
                .map(|i| (p[a][i] - p[b][i]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(
                d > tol,
                "{name}: vertices {a} and {b} coincide ({:?})",
                p[a]
            );
        }
    }
}

#[test]
fn closed_inputs_give_closed_manifolds_and_open_ones_keep_their_boundary() {
    for (name, mesh, options, closed) in meshes() {
        for rate in [1, 2, 3, 4] {
            for triangles in [false, true] {
                let t = tessellate_mesh(&mesh, &options, rate, triangles).unwrap();
                let r = t.rate as usize;
                assert!(r == rate as usize || (r == rate as usize + 1 && rate % 2 == 1));
                let (undirected, directed) = edge_counts(&t);
                // Consistently oriented: no directed edge twice.
                assert!(
                    directed.values().all(|&c| c == 1),
                    "{name} rate {rate} tri {triangles}: {:?}",
                    directed.iter().filter(|x| *x.1 > 1).collect::<Vec<_>>()
                );
                if closed {
                    assert!(
                        undirected.values().all(|&c| c == 2),
                        "{name} rate {rate}: an edge without two faces"
                    );
                }
                let expect: Vec<usize> = input_boundary_loops(&mesh, &options)
                    .iter()
                    .map(|l| l * r)
                    .collect();
                assert_eq!(output_boundary_loops(&t), expect, "{name} rate {rate}");
                assert_eq!(closed, expect.is_empty(), "{name}");
                // Euler characteristic of the surface is kept.
                let chi = |v: usize, e: usize, f: usize| v as i64 - e as i64 + f as i64;
                let s = LimitSurface::new(&mesh, options).unwrap();
                let (topo, _) = Topology::from_mesh(&mesh, &options).unwrap();
                let live: Vec<usize> = (0..topo.num_faces())
                    .filter(|&f| s.has_surface(f))
                    .collect();
                let mut verts = std::collections::HashSet::new();
                let mut edges = std::collections::HashSet::new();
                for &f in &live {
                    verts.extend(topo.face_vertices(f).iter().copied());
                    edges.extend(topo.face_edge_list(f).iter().copied());
                }
                assert_eq!(
                    chi(t.num_vertices(), undirected.len(), t.num_faces()),
                    chi(verts.len(), edges.len(), live.len()),
                    "{name} rate {rate}"
                );
                assert_no_duplicates(name, &t.positions, 1e-12);
                for (i, n) in t.normals.iter().enumerate() {
                    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    assert!((len - 1.0).abs() < 1e-12, "{name}: normal {i} is {n:?}");
                }
                assert_eq!(t.source.len(), t.num_faces());
                let size = if triangles { 3 } else { 4 };
                assert!((0..t.num_faces()).all(|f| t.face(f).len() == size));
                t.to_polymesh().unwrap();
            }
        }
    }
}

#[test]
fn face_counts_and_sources() {
    let (c, o) = cube();
    let t = tessellate_mesh(&c, &o, 5, false).unwrap();
    assert_eq!(t.num_faces(), 6 * 25);
    assert_eq!(t.num_vertices(), 8 + 12 * 4 + 6 * 16);
    assert!(t.source[..25].iter().all(|&s| s == (0, 0)));
    assert_eq!(t.source[25], (1, 0));
    let t = tessellate_mesh(&c, &o, 5, true).unwrap();
    assert_eq!(t.num_faces(), 2 * 6 * 25);
    // The hut: a hexagon, six quads, six triangles; rate 3 becomes 4.
    let (h, ho) = obj(include_str!("../../../../examples/meshes/hut.obj"));
    let t = tessellate_mesh(&h, &ho, 3, false).unwrap();
    assert_eq!(t.rate, 4);
    assert_eq!(t.num_faces(), 6 * 16 + 6 * 4 + 6 * 3 * 4);
    // Sub-faces in order within each face.
    let hexagon = (0..h.num_faces()).find(|&f| h.face(f).len() == 6).unwrap() as u32;
    let subs: Vec<u32> = t
        .source
        .iter()
        .filter(|s| s.0 == hexagon)
        .map(|s| s.1)
        .collect();
    assert_eq!(subs, (0..6).flat_map(|j| [j; 4]).collect::<Vec<_>>());
}

#[test]
fn holes_and_dropped_faces_produce_nothing() {
    let (mut c, o) = cube();
    c.tags.holes = vec![0, 3];
    let t = tessellate_mesh(&c, &o, 2, false).unwrap();
    assert_eq!(t.num_faces(), 4 * 4);
    assert!(t.source.iter().all(|s| s.0 != 0 && s.0 != 3));
    // Boundary "none": the faces at the grid's boundary are dropped.
    let (g, _) = obj(include_str!("../../../../examples/meshes/grid.obj"));
    let none = Options {
        boundary: BoundaryInterpolation::None,
        ..Options::default()
    };
    let t = tessellate_mesh(&g, &none, 2, false).unwrap();
    assert_eq!(t.num_faces(), 4 * 4);
}

/// On a regular torus every face is one bicubic B-spline patch: the samples are the
/// B-spline surface at `(a / rate, b / rate)`, and the normals its normals.
#[test]
fn regular_torus_samples_the_bspline_surface() {
    let (n, m, rate) = (7usize, 5usize, 3usize);
    let mesh = torus(n, m);
    let t = tessellate_mesh(&mesh, &Options::default(), rate as u32, false).unwrap();
    let p = mesh.positions();
    let s = LimitSurface::new(&mesh, Options::default()).unwrap();
    for i in 0..n {
        for j in 0..m {
            let f = i * m + j;
            let mut cp = [[[0.0; 3]; 4]; 4];
            for a in 0..4 {
                for b in 0..4 {
                    cp[a][b] = p[((i + n + a - 1) % n) * m + (j + m + b - 1) % m];
                }
            }
            for b in 0..=rate {
                for a in 0..=rate {
                    // The vertex at (a, b): a corner of cell (min(a, r-1), min(b, r-1)).
                    let (ca, cb) = (a.min(rate - 1), b.min(rate - 1));
                    let cell = t.face(f * rate * rate + cb * rate + ca);
                    let corner = match (a - ca, b - cb) {
                        (0, 0) => 0,
                        (1, 0) => 1,
                        (1, 1) => 2,
                        _ => 3,
                    };
                    let v = cell[corner] as usize;
                    let (u, w) = (a as f64 / rate as f64, b as f64 / rate as f64);
                    let d = bspline::eval(&cp, u, w);
                    let e = s.eval(f as u32, u, w).unwrap();
                    for k in 0..3 {
                        assert!(
                            (t.positions[v][k] - d.p[k]).abs() < 1e-14,
                            "face {f} ({a}, {b})"
                        );
                        assert!((t.normals[v][k] - d.normal()[k]).abs() < 1e-12);
                        assert!((e.p[k] - d.p[k]).abs() < 1e-14);
                    }
                }
            }
        }
    }
}

#[test]
fn tessellate_takes_a_prebuilt_surface() {
    let m = mixed();
    let o = Options::default();
    let s = LimitSurface::new(&m, o).unwrap();
    let a = tessellate(&s, &m, 2, false).unwrap();
    let b = tessellate_mesh(&m, &o, 2, false).unwrap();
    assert_eq!(a, b);
}

#[test]
fn writes_obj_ply_and_stl() {
    let (c, o) = creased_cube();
    let t = tessellate_mesh(&c, &o, 3, false).unwrap();
    let mesh = t.to_polymesh().unwrap();

    // OBJ: bit-exact round trip with normals.
    let mut out = Vec::new();
    let opts = WriteOptions {
        normals: Some(&t.normals),
        ..WriteOptions::default()
    };
    write_obj(&mut out, &mesh, &opts).unwrap();
    let back = parse_obj(&out, "t.obj").unwrap();
    assert_eq!(back.mesh.positions(), &t.positions[..]);
    assert_eq!(back.normals, t.normals);
    assert_eq!(back.mesh.face_verts(), &t.face_verts[..]);

    // PLY: header + 48 bytes per vertex + 17 per quad; exact round trip.
    let mut out = Vec::new();
    write_ply(
        &mut out,
        &t.positions,
        Some(&t.normals),
        &t.face_offsets,
        &t.face_verts,
    )
    .unwrap();
    let header_len = out.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&out[..header_len]).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    assert!(header.contains(&format!("element vertex {}\n", t.num_vertices())));
    assert!(header.contains(&format!("element face {}\n", t.num_faces())));
    assert!(header.contains("property list uchar int vertex_indices\n"));
    assert_eq!(
        out.len(),
        header_len + 48 * t.num_vertices() + 17 * t.num_faces()
    );
    let ply = read_ply(&out).unwrap();
    assert_eq!(ply.positions, t.positions);
    assert_eq!(ply.normals.as_ref(), Some(&t.normals));
    assert_eq!(ply.face_offsets, t.face_offsets);
    assert_eq!(ply.face_verts, t.face_verts);

    // STL: quads fan-triangulated, f32 vertices, outward normals.
    let mut out = Vec::new();
    write_stl(
        &mut out,
        &t.positions,
        &t.face_offsets,
        &t.face_verts,
        "cube",
    )
    .unwrap();
    assert_eq!(out.len(), 84 + 50 * 2 * t.num_faces());
    let (_, tris) = read_stl(&out).unwrap();
    assert_eq!(tris.len(), 2 * t.num_faces());
    let q = t.face(0);
    assert_eq!(
        tris[0].vertices[1],
        t.positions[q[1] as usize].map(|x| x as f32)
    );
    let centre = [0.0f32; 3];
    for tri in &tris {
        let v = tri.vertices[0];
        let out_dir: f32 = (0..3).map(|k| (v[k] - centre[k]) * tri.normal[k]).sum();
        assert!(out_dir > 0.0, "STL normals point outward");
    }
}
