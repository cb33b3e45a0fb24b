//! OBJ objects, groups and materials (`o`, `g`, `usemtl`, `mtllib`) carried through
//! refinement: read per face, given by every scheme to all the children of a face (checked
//! by where the children lie, not by their numbering), written back when they change;
//! smoothing groups noted and dropped.

use std::collections::BTreeMap;

use subsurf::io::{parse_mesh, parse_obj, write_obj, WriteOptions};
use subsurf::mesh::{FaceGroups, PolyMesh};
use subsurf::scheme::Adjustable;
use subsurf::{subdivide, Mixed, Scheme, SubdivideOptions};

/// A unit cube in two objects and three groups, under two materials, with smoothing
/// groups; `extra` goes before the faces.
fn cube(extra: &str) -> String {
    format!(
        "mtllib first.mtl\n{extra}v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         o box_a\ng bottom\nusemtl red\ns 1\nf 1 4 3 2\ng top sides\nf 5 6 7 8\nusemtl blue\nf 1 2 6 5\n\
         o box_b\nf 2 3 7 6\nusemtl red\ns off\nf 3 4 8 7\nmtllib second.mtl\nf 4 1 5 8\n"
    )
}

/// The outward axis of the cube face that a point lies over, seen from the centre: the
/// axis (0, 1, 2) and sign of the largest coordinate of `p - (0.5, 0.5, 0.5)`.
fn side(p: [f64; 3]) -> (usize, bool) {
    let d = p.map(|x| x - 0.5);
    let k = (0..3)
        .max_by(|&a, &b| d[a].abs().total_cmp(&d[b].abs()))
        .unwrap();
    (k, d[k] > 0.0)
}

fn centroid(m: &PolyMesh, f: usize) -> [f64; 3] {
    let fv = m.face(f);
    let mut c = [0.0; 3];
    for &v in fv {
        for (c, x) in c.iter_mut().zip(m.positions()[v as usize]) {
            *c += x / fv.len() as f64;
        }
    }
    c
}

/// A side of the cube: an axis and whether it is the far one.
type Side = (usize, bool);

/// The (object, group, material) of each side of the cube in `m`, from the faces over it;
/// `None` if two faces over one side disagree.
fn states_by_side(m: &PolyMesh) -> Option<BTreeMap<Side, [Option<String>; 3]>> {
    let mut by_side = BTreeMap::new();
    for f in 0..m.num_faces() {
        let s = m.groups.state(f)?;
        let state = [s.object.clone(), s.group.clone(), s.material.clone()];
        if *by_side.entry(side(centroid(m, f))).or_insert(state.clone()) != state {
            return None;
        }
    }
    Some(by_side)
}

/// Faces per material.
fn per_material(m: &PolyMesh) -> BTreeMap<String, usize> {
    let mut count = BTreeMap::new();
    for f in 0..m.num_faces() {
        let s = m.groups.state(f).unwrap();
        *count
            .entry(s.material.clone().unwrap_or_default())
            .or_default() += 1;
    }
    count
}

/// The reader keeps each face's state and the libraries; refined with every scheme that
/// splits faces (Catmull-Clark, bilinear, adjustable, NURSS; at levels 1 and 2) each
/// child lies over its parent's side of the cube and has its parent's state, the counts
/// per material are the parents' times `4^L`, and the written OBJ reads back the same:
/// `mtllib` lines first, a statement where the state changes.
#[test]
fn refined_faces_keep_their_parents_groups() {
    let obj = parse_obj(cube("").as_bytes(), "cube.obj").unwrap();
    let m = &obj.mesh;
    assert_eq!(m.groups.material_libraries, ["first.mtl", "second.mtl"]);
    assert_eq!(m.groups.states.len(), 5);
    let base = states_by_side(m).unwrap();
    assert_eq!(base.len(), 6);
    assert_eq!(
        base[&(2, false)],
        [
            Some("box_a".into()),
            Some("bottom".into()),
            Some("red".into())
        ]
    );
    assert_eq!(
        base[&(2, true)],
        [
            Some("box_a".into()),
            Some("top sides".into()),
            Some("red".into())
        ]
    );
    assert_eq!(
        base[&(0, false)],
        [
            Some("box_b".into()),
            Some("top sides".into()),
            Some("red".into())
        ]
    );
    let schemes = [
        Scheme::CatmullClark,
        Scheme::Bilinear,
        Scheme::Adjustable(Mixed::all(Adjustable::new(0.3).unwrap())),
        Scheme::Nurss,
    ];
    for scheme in schemes {
        for levels in [1, 2] {
            let opts = SubdivideOptions {
                levels,
                scheme,
                ..Default::default()
            };
            let r = subdivide(m, &opts).unwrap().mesh;
            assert_eq!(r.num_faces(), 6 << (2 * levels));
            assert_eq!(
                states_by_side(&r).as_ref(),
                Some(&base),
                "{scheme:?} {levels}"
            );
            let counts = per_material(&r);
            assert_eq!(counts["red"], 4 << (2 * levels), "{scheme:?} {levels}");
            assert_eq!(counts["blue"], 2 << (2 * levels));
            assert_eq!(r.groups.material_libraries, m.groups.material_libraries);
            let mut text = Vec::new();
            write_obj(&mut text, &r, &WriteOptions::default()).unwrap();
            let back = parse_obj(&text, "back.obj").unwrap().mesh;
            assert_eq!(states_by_side(&back).as_ref(), Some(&base));
            let text = String::from_utf8(text).unwrap();
            let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
            assert_eq!(lines[..2], ["mtllib first.mtl", "mtllib second.mtl"]);
            // One statement per change of a part, as in the input: 2 o, 2 g, 3 usemtl.
            for (kw, n) in [("o ", 2), ("g ", 2), ("usemtl ", 3)] {
                let written = lines.iter().filter(|l| l.starts_with(kw)).count();
                assert_eq!(written, n, "{kw}\n{text}");
            }
        }
    }
}

/// Holes are left out with their children, and the groups of the faces kept follow
/// them; with `keep_holes` the holes' children keep theirs.
#[test]
fn holes_leave_out_their_groups() {
    let obj = parse_obj(cube("").as_bytes(), "cube.obj").unwrap();
    let mut m = obj.mesh;
    m.tags.holes = vec![2];
    for keep_holes in [false, true] {
        let opts = SubdivideOptions {
            levels: 2,
            keep_holes,
            ..Default::default()
        };
        let r = subdivide(&m, &opts).unwrap().mesh;
        let n = if keep_holes { 6 } else { 5 };
        assert_eq!(r.num_faces(), 16 * n);
        assert_eq!(r.groups.face_states.len(), 16 * n);
        let counts = per_material(&r);
        assert_eq!(counts["blue"], if keep_holes { 32 } else { 16 });
        let by_side = states_by_side(&r).unwrap();
        assert_eq!(by_side.len(), n);
    }
}

/// Loop's triangle split: the octahedron's eight faces, each its own material, give each
/// of their 4^L children their material (each child lies in its parent's octant).
#[test]
fn loop_children_keep_their_parents_material() {
    let mut text = String::new();
    for p in ["1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1"] {
        text += &format!("v {p}\n");
    }
    let faces = [
        [1, 3, 5],
        [3, 2, 5],
        [2, 4, 5],
        [4, 1, 5],
        [3, 1, 6],
        [2, 3, 6],
        [4, 2, 6],
        [1, 4, 6],
    ];
    for (i, f) in faces.iter().enumerate() {
        text += &format!("usemtl m{i}\nf {} {} {}\n", f[0], f[1], f[2]);
    }
    let m = parse_obj(text.as_bytes(), "octa.obj").unwrap().mesh;
    let octant = |p: [f64; 3]| p.map(|x| x > 0.0);
    let material = |m: &PolyMesh, f: usize| m.groups.state(f).unwrap().material.clone().unwrap();
    let mut expected = BTreeMap::new();
    for f in 0..8 {
        expected.insert(octant(centroid(&m, f)), material(&m, f));
    }
    for levels in [1, 2, 3] {
        let opts = SubdivideOptions {
            levels,
            scheme: Scheme::Loop,
            ..Default::default()
        };
        let r = subdivide(&m, &opts).unwrap().mesh;
        assert_eq!(r.num_faces(), 8 << (2 * levels));
        for f in 0..r.num_faces() {
            assert_eq!(
                material(&r, f),
                expected[&octant(centroid(&r, f))],
                "level {levels}"
            );
        }
    }
}

/// A mesh without groups is written without `o`, `g`, `usemtl` or `mtllib` lines; a file
/// whose statements come after its faces groups none of them; a bad grouping is refused
/// by validation.
#[test]
fn no_groups_write_no_statements() {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    let m = parse_obj(text.as_bytes(), "q.obj").unwrap().mesh;
    assert!(m.groups.is_empty());
    let r = subdivide(
        &m,
        &SubdivideOptions {
            levels: 2,
            ..Default::default()
        },
    )
    .unwrap()
    .mesh;
    assert!(r.groups.is_empty());
    let mut out = Vec::new();
    write_obj(&mut out, &r, &WriteOptions::default()).unwrap();
    let out = String::from_utf8(out).unwrap();
    for kw in ["o ", "g ", "usemtl", "mtllib"] {
        assert!(!out.lines().any(|l| l.starts_with(kw)), "{kw}");
    }
    let late = parse_obj(format!("{text}g after\n").as_bytes(), "q.obj")
        .unwrap()
        .mesh;
    assert_eq!(late.groups, FaceGroups::default());
    let mut bad = m.clone();
    bad.groups.face_states = vec![3];
    assert!(bad
        .validate()
        .unwrap_err()
        .to_string()
        .contains("face 0 has state 3"));
}

/// Smoothing groups are noted (not kept): a subdivision surface is smooth but at creases.
#[test]
fn smoothing_groups_are_noted() {
    let f = parse_mesh(cube("").as_bytes(), "cube.obj").unwrap();
    assert_eq!(f.obj.smoothing_groups, 1);
    assert!(
        f.ignored
            .iter()
            .any(|n| n.contains("1 smoothing-group statement(s) (s)")),
        "{:?}",
        f.ignored
    );
    let f = parse_mesh(b"v 0 0 0\nv 1 0 0\nv 0 1 0\ns off\nf 1 2 3\n", "t.obj").unwrap();
    assert!(f.ignored.is_empty());
}
