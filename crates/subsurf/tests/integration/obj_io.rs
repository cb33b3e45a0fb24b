//! The OBJ reader and writer, and atomic output, as specifications.

use std::io;
use std::path::Path;

use subsurf::io::write_atomically;
use subsurf::io::{
    parse_obj, read_obj, write_obj, FileOptions, ObjError, ObjFile, UnsupportedTag, WriteOptions,
};
use subsurf::mesh::{
    BoundaryInterpolation, Corner, Crease, CreaseMethod, Options, PolyMesh, TriangleSubdivision,
};

const NAME: &str = "test.obj";

fn parse(text: &str) -> ObjFile {
    match parse_obj(text.as_bytes(), NAME) {
        Ok(obj) => obj,
        Err(e) => panic!("parse failed: {e}\n--- input ---\n{text}"),
    }
}

fn faces(obj: &ObjFile) -> Vec<Vec<u32>> {
    obj.mesh.faces().map(<[u32]>::to_vec).collect()
}

/// Parsing `text` fails at `line` with a message containing `phrase`; the error's display
/// names the file and the line.
#[track_caller]
fn assert_error(text: &str, line: usize, phrase: &str) -> ObjError {
    assert_error_bytes(text.as_bytes(), line, phrase)
}

#[track_caller]
fn assert_error_bytes(bytes: &[u8], line: usize, phrase: &str) -> ObjError {
    let e = match parse_obj(bytes, NAME) {
        Ok(_) => panic!("expected an error containing {phrase:?} at line {line}"),
        Err(e) => e,
    };
    let shown = e.to_string();
    assert_eq!(e.line, Some(line), "wrong line in {shown:?}");
    assert_eq!(e.source_name, NAME);
    assert!(
        shown.starts_with(&format!("{NAME}:{line}: ")),
        "display {shown:?}"
    );
    assert!(
        shown.contains(phrase),
        "{shown:?} does not contain {phrase:?}"
    );
    e
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

// ---------------------------------------------------------------------------------------
// Vertices and faces
// ---------------------------------------------------------------------------------------

#[test]
fn positions_are_parsed_exactly_and_w_or_colour_is_ignored() {
    let obj = parse(
        "v 0.1 -2.5e-3 1e10\n\
         v 1 2 3 1.0\n\
         v 4 5 6 0.5 0.25 1\n\
         v 7 8 9 0.5 0.25 1 1\n\
         v\t+1\t.5  5.\n",
    );
    assert_eq!(
        obj.mesh.positions(),
        &[
            [0.1, -2.5e-3, 1e10],
            [1.0, 2.0, 3.0],
            [4.0, 5.0, 6.0],
            [7.0, 8.0, 9.0],
            [1.0, 0.5, 5.0]
        ]
    );
    assert_eq!(obj.mesh.num_faces(), 0);
}

#[test]
fn face_with_plain_indices() {
    let obj = parse(&format!("{QUAD}f 1 2 3 4\n"));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2, 3]]);
    assert_eq!(obj.face_texcoords, None);
    assert_eq!(obj.face_normals, None);
    assert_eq!(obj.face_lines, vec![5]);
}

#[test]
fn face_with_texture_indices() {
    let obj = parse(&format!(
        "{QUAD}vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5\nf 1/1 2/2 3/3 4/4\n"
    ));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2, 3]]);
    assert_eq!(
        obj.texcoords,
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.5, 0.0, 0.0]
        ]
    );
    assert_eq!(obj.face_texcoords, Some(vec![0, 1, 2, 3]));
    assert_eq!(obj.face_normals, None);
}

#[test]
fn face_with_normal_indices() {
    let obj = parse(&format!("{QUAD}vn 0 0 1\nf 1//1 2//1 3//1 4//1\n"));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2, 3]]);
    assert_eq!(obj.normals, vec![[0.0, 0.0, 1.0]]);
    assert_eq!(obj.face_texcoords, None);
    assert_eq!(obj.face_normals, Some(vec![0, 0, 0, 0]));
}

#[test]
fn face_with_texture_and_normal_indices() {
    let obj = parse(&format!(
        "{QUAD}vt 0 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvn 0 0 -1\nf 1/4/2 2/3/2 3/2/1 4/1/1\n"
    ));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2, 3]]);
    assert_eq!(obj.face_texcoords, Some(vec![3, 2, 1, 0]));
    assert_eq!(obj.face_normals, Some(vec![1, 1, 0, 0]));
}

#[test]
fn corner_attributes_are_none_unless_every_corner_has_one() {
    let obj = parse(&format!(
        "{QUAD}v 2 0 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf 1/1 3/1 4/1 5/1\n"
    ));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2], vec![0, 2, 3, 4]]);
    assert_eq!(obj.face_texcoords, Some(vec![0; 7]));
    assert_eq!(obj.face_normals, None);
    assert_eq!(obj.mesh.face_varying.len(), 1);
    assert_eq!(obj.mesh.face_varying[0].name(), "uv");
}

#[test]
fn faces_with_and_without_texture_coordinates_are_refused_at_the_line() {
    // Texture coordinates are face-varying data: dropping them silently would lose the
    // mapping, and refining with half of them is impossible.
    let e = parse_obj(format!("{QUAD}vt 0 0\nf 1/1 2 3\n").as_bytes(), NAME).unwrap_err();
    assert_eq!(e.line, Some(6), "{e}");
    assert!(e.message.contains("texture coordinates"), "{e}");
    let text = format!("{QUAD}v 2 0 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 3 4 5\n");
    let e = parse_obj(text.as_bytes(), NAME).unwrap_err();
    assert_eq!(e.line, Some(8), "{e}");
}

#[test]
fn negative_indices_are_relative_to_what_is_defined_so_far() {
    let obj = parse(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n\
         f -3/-3/-1 -2/-2/-1 -1/-1/-1\n\
         v 0 1 0\n\
         f -4/-3 -2/-1 -1/-2\n",
    );
    assert_eq!(faces(&obj), vec![vec![0, 1, 2], vec![0, 2, 3]]);
    assert_eq!(obj.face_lines, vec![8, 10]);
}

#[test]
fn faces_may_refer_to_vertices_defined_later() {
    let obj = parse("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    assert_eq!(faces(&obj), vec![vec![0, 1, 2]]);
    assert_eq!(obj.face_lines, vec![1]);
}

#[test]
fn polygons_of_any_size_and_isolated_vertices_are_kept() {
    let mut text = String::new();
    for i in 0..40 {
        let a = f64::from(i) * std::f64::consts::TAU / 40.0;
        text.push_str(&format!("v {} {} 0\n", a.cos(), a.sin()));
    }
    text.push_str("v 5 5 5\nf");
    for i in 1..=40 {
        text.push_str(&format!(" {i}"));
    }
    text.push('\n');
    let obj = parse(&text);
    assert_eq!(obj.mesh.num_vertices(), 41);
    assert_eq!(obj.mesh.face(0), (0..40).collect::<Vec<u32>>().as_slice());
}

#[test]
fn crlf_line_ends() {
    let obj = parse("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n# done\r\n");
    assert_eq!(faces(&obj), vec![vec![0, 1, 2]]);
    assert_eq!(obj.face_lines, vec![4]);
}

/// Lines may end with a lone CR (old Mac OS files), and line numbers count them, in
/// files that mix them with LF and CRLF too.
#[test]
fn cr_line_ends() {
    let obj = parse("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r# done\r");
    assert_eq!(faces(&obj), vec![vec![0, 1, 2]]);
    assert_eq!(obj.face_lines, vec![4]);
    let obj = parse("# mixed\r\nv 0 0 0\rv 1 0 0\nv 0 1 0\r\rf 1 2 3");
    assert_eq!(obj.face_lines, vec![6]);
    assert_error("v 0 0 0\rv 1 0 0\rv 1 x 0\r", 3, "v: 'x' is not a number");
    assert_error(
        "v 0 0 0\r\nv 1 0 0\rf 1 2 3\r\n",
        3,
        "f: vertex index 3 is out",
    );
    // A continued line goes on after a CR as after a LF.
    let obj = parse("v 0 0 \\\r0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r");
    assert_eq!(obj.face_lines, vec![5]);
    assert_eq!(obj.mesh.num_vertices(), 3);
}

/// A line that is not text is refused with the message about its first byte that is
/// not: a control character, or a byte that is not UTF-8, whichever comes first.
#[test]
fn the_first_byte_that_is_not_text_decides() {
    assert_error_bytes(b"v 0 0 0\n# \x01 \xff\n", 2, "control character 0x01");
    assert_error_bytes(b"v 0 0 0\n# \xff \x01\n", 2, "line 2 is not valid UTF-8");
    // A sequence cut off at the end of the line.
    assert_error_bytes(b"# \xc3\n", 1, "line 1 is not valid UTF-8");
    assert_error_bytes(b"# caf\xc3\xa9 \x02\n", 1, "control character 0x02");
}

#[test]
fn backslash_continuation() {
    let obj = parse("v 0 0 0\nv 1 0 \\\n0\nv 0 1 0\r\nf 1 \\\r\n 2\\\n3\nv 1 1 1\n");
    assert_eq!(
        obj.mesh.positions(),
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 1.0]
        ]
    );
    assert_eq!(faces(&obj), vec![vec![0, 1, 2]]);
    // The face starts on line 5.
    assert_eq!(obj.face_lines, vec![5]);
    // Errors in a continued line name its first physical line.
    assert_error(
        "v 0 0 0\nv 1 0 0\nf 1 \\\n2 \\\n3 x\n",
        3,
        "malformed vertex reference 'x'",
    );
    // A comment ends the logical line: a trailing backslash in a comment does not continue.
    let obj = parse("# C:\\models\\\nv 0 0 0\n");
    assert_eq!(obj.mesh.num_vertices(), 1);
    // But a backslash before a comment continues.
    let obj = parse("v 0 0 \\ # z follows\n1\n");
    assert_eq!(obj.mesh.positions(), &[[0.0, 0.0, 1.0]]);
    // The backslash may be followed by spaces.
    let obj = parse("v 0 0 \\  \t\n 0\n");
    assert_eq!(obj.mesh.positions(), &[[0.0; 3]]);
    // A continuation at the end of the file just ends the line.
    let obj = parse("v 0 0 0 \\");
    assert_eq!(obj.mesh.num_vertices(), 1);
}

#[test]
fn comments_and_blank_lines_are_ignored() {
    let obj = parse(
        "# a comment\n\n   \n\t\nv 0 0 0 # trailing comment\nv 1 0 0#no space\nv 0 1 0\n\
         f 1 2 3 # a face\n#f 1 2 4\n",
    );
    assert_eq!(obj.mesh.num_vertices(), 3);
    assert_eq!(faces(&obj), vec![vec![0, 1, 2]]);
}

#[test]
fn other_statements_are_ignored() {
    let obj = parse(&format!(
        "mtllib a.mtl\no thing\ng group1 group2\ns 1\ns off\nusemtl red\n{QUAD}\
         vp 0.5 0.5\nl 1 2 3\np 1 2\ncstype bspline\ndeg 3\ncurv 0 1 1 2 3 4\nparm u 0 0 0 0 1 1 1 1\n\
         surf 0 1 0 1 1 2 3 4\nend\nfrobnicate 1 2 3\nf 1 2 3 4\n"
    ));
    assert_eq!(faces(&obj), vec![vec![0, 1, 2, 3]]);
    assert!(obj.unsupported_tags.is_empty());
}

#[test]
fn empty_input_is_an_empty_mesh() {
    for text in [
        "",
        "\n",
        "# nothing\n",
        "\u{feff}# with a byte-order mark\n",
    ] {
        let obj = parse(text);
        assert_eq!(obj.mesh.num_vertices(), 0);
        assert_eq!(obj.mesh.num_faces(), 0);
        assert!(obj.mesh.tags.is_empty());
        assert!(obj.face_lines.is_empty());
        assert_eq!(obj.face_texcoords, None);
    }
}

#[test]
fn a_point_cloud_without_faces_is_fine() {
    let obj = parse("v 1 2 3\nv 4 5 6\n");
    assert_eq!(obj.mesh.num_vertices(), 2);
    assert_eq!(obj.mesh.num_faces(), 0);
}

// ---------------------------------------------------------------------------------------
// Tags
// ---------------------------------------------------------------------------------------

fn crease(v0: u32, v1: u32, sharpness: f32) -> Crease {
    Crease { v0, v1, sharpness }
}

#[test]
fn crease_tag_for_one_edge() {
    let obj = parse(&format!("{QUAD}f 1 2 3 4\nt crease 2/1/0 0 1 2.5\n"));
    assert_eq!(obj.mesh.tags.creases, vec![crease(0, 1, 2.5)]);
}

#[test]
fn crease_chain_with_one_shared_sharpness() {
    let obj = parse(&format!("{QUAD}f 1 2 3 4\nt crease 4/1/0 0 1 2 3 1.5\n"));
    assert_eq!(
        obj.mesh.tags.creases,
        vec![crease(0, 1, 1.5), crease(1, 2, 1.5), crease(2, 3, 1.5)]
    );
}

#[test]
fn crease_chain_with_one_sharpness_per_edge() {
    let obj = parse(&format!(
        "{QUAD}f 1 2 3 4\nt crease 5/4/0 0 1 2 3 0 1 2 3 0.1\n"
    ));
    assert_eq!(
        obj.mesh.tags.creases,
        vec![
            crease(0, 1, 1.0),
            crease(1, 2, 2.0),
            crease(2, 3, 3.0),
            crease(3, 0, 0.1)
        ]
    );
}

#[test]
fn crease_without_sharpness_is_infinitely_sharp() {
    let obj = parse(&format!("{QUAD}f 1 2 3 4\nt crease 3/0/0 0 1 2\n"));
    assert_eq!(
        obj.mesh.tags.creases,
        vec![crease(0, 1, 10.0), crease(1, 2, 10.0)]
    );
}

#[test]
fn crease_sharpness_is_read_as_the_nearest_f32() {
    let obj = parse(&format!("{QUAD}t crease 2/1/0 0 1 0.1\n"));
    assert_eq!(
        obj.mesh.tags.creases[0].sharpness.to_bits(),
        0.1f32.to_bits()
    );
}

#[test]
fn corner_tags() {
    let obj = parse(&format!(
        "{QUAD}f 1 2 3 4\nt corner 1/1/0 0 3\nt corner 2/1/0 1 2 0.5\nt corner 2/2/0 3 0 4 5\nt corner 1/0/0 2\n"
    ));
    let c = |vertex, sharpness| Corner { vertex, sharpness };
    assert_eq!(
        obj.mesh.tags.corners,
        vec![
            c(0, 3.0),
            c(1, 0.5),
            c(2, 0.5),
            c(3, 4.0),
            c(0, 5.0),
            c(2, 10.0)
        ]
    );
}

#[test]
fn hole_tags() {
    let obj = parse(&format!(
        "{QUAD}v 2 0 0\nf 1 2 3\nf 1 3 4\nf 2 5 3\nt hole 2/0/0 0 2\nt hole 1/0/0 1\n"
    ));
    assert_eq!(obj.mesh.tags.holes, vec![0, 2, 1]);
}

#[test]
fn scheme_option_tags() {
    let obj = parse(&format!(
        "{QUAD}t interpolateboundary 1/0/0 1\nt creasemethod 0/0/1 chaikin\nt smoothtriangles 0/0/1 smooth\n"
    ));
    assert_eq!(
        obj.options,
        FileOptions {
            boundary: Some(BoundaryInterpolation::EdgeAndCorner),
            crease_method: Some(CreaseMethod::Chaikin),
            triangles: Some(TriangleSubdivision::Smooth),
            face_varying: None,
        }
    );
    let o = parse("t interpolateboundary 1/0/0 0\nt creasemethod 0/0/1 uniform\nt smoothtriangles 0/0/1 catmark\n");
    assert_eq!(o.options.boundary, Some(BoundaryInterpolation::None));
    assert_eq!(o.options.crease_method, Some(CreaseMethod::Uniform));
    assert_eq!(o.options.triangles, Some(TriangleSubdivision::Catmark));
    let o = parse("t interpolateboundary 1/0/0 2\nt creasemethod 0/0/1 normal\n");
    assert_eq!(o.options.boundary, Some(BoundaryInterpolation::EdgeOnly));
    assert_eq!(o.options.crease_method, Some(CreaseMethod::Uniform));
    // Without tags, nothing is set and the defaults apply.
    assert_eq!(parse(QUAD).options, FileOptions::default());
    let defaults = Options {
        boundary: BoundaryInterpolation::None,
        ..Options::default()
    };
    assert_eq!(parse(QUAD).options.resolve(defaults), defaults);
}

#[test]
fn tags_may_precede_what_they_refer_to() {
    let obj = parse("t crease 2/1/0 0 1 1\nt hole 1/0/0 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(obj.mesh.tags.creases, vec![crease(0, 1, 1.0)]);
    assert_eq!(obj.mesh.tags.holes, vec![0]);
}

#[test]
fn unsupported_tags_are_recorded_with_their_lines() {
    let obj = parse(&format!(
        "{QUAD}f 1 2 3 4\n\
         t vertexedit 1/0/1 0 add\n\
         t edgeedit 2/1/2 0 1 3.0 set sharpness\n\
         t faceedit whatever\n\
         t facevaryinginterpolateboundary 1/0/0 1\n\
         t facevaryingpropagatecorners 1/0/0 1\n"
    ));
    let names: Vec<(usize, &str)> = obj
        .unsupported_tags
        .iter()
        .map(|t| (t.line, t.name.as_str()))
        .collect();
    assert_eq!(
        names,
        vec![(6, "vertexedit"), (7, "edgeedit"), (8, "faceedit"),]
    );
    assert_eq!(
        obj.unsupported_tags[0],
        UnsupportedTag {
            line: 6,
            name: "vertexedit".into()
        }
    );
}

// ---------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------

#[test]
fn error_display_names_file_and_line() {
    let e = assert_error("v 0 0 0\nv 1 2 x\n", 2, "'x' is not a number");
    assert_eq!(e.to_string(), "test.obj:2: v: 'x' is not a number");
}

#[test]
fn vertex_errors() {
    assert_error("v 1 2 x\n", 1, "'x' is not a number");
    assert_error("v 1 2\n", 1, "needs 3 coordinates");
    assert_error("v\n", 1, "needs 3 coordinates");
    assert_error("v 1 2 3 4 5\n", 1, "found 5 numbers");
    assert_error("v nan 0 0\n", 1, "non-finite coordinate 'nan'");
    assert_error("v 0 inf 0\n", 1, "non-finite coordinate");
    assert_error("v 0 0 -infinity\n", 1, "non-finite coordinate");
    assert_error("v 0 0 0\nv 1e999 0 0\n", 2, "non-finite coordinate '1e999'");
    assert_error("vt\n", 1, "needs at least 1 number");
    assert_error("vt 0 0 0 0\n", 1, "expected u [v [w]]");
    assert_error("vt 0 nan\n", 1, "non-finite texture coordinate");
    assert_error("vn 0 1\n", 1, "needs 3 numbers");
    assert_error("vn 0 1 z\n", 1, "'z' is not a number");
    assert_error("vn 0 1 inf\n", 1, "non-finite normal component");
}

#[test]
fn index_zero_is_an_error() {
    assert_error(&format!("{QUAD}f 0 1 2\n"), 5, "OBJ indices start at 1");
    assert_error(
        &format!("{QUAD}vt 0 0\nf 1/0 2/1 3/1\n"),
        6,
        "OBJ indices start at 1",
    );
    assert_error(
        &format!("{QUAD}vn 0 0 1\nf 1//0 2//1 3//1\n"),
        6,
        "OBJ indices start at 1",
    );
    assert_error(&format!("{QUAD}f -0 1 2\n"), 5, "OBJ indices start at 1");
}

#[test]
fn out_of_range_vertex_is_reported_at_the_face_with_the_final_count() {
    let e = assert_error(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\nv 1 1 1\n",
        4,
        "vertex index 7 is out of range: the file has 4 vertices",
    );
    assert_eq!(
        e.to_string(),
        "test.obj:4: f: vertex index 7 is out of range: the file has 4 vertices"
    );
    // The first bad face in the file is reported, not the worst one.
    assert_error(
        &format!("{QUAD}f 1 2 9\nf 1 2 50\nf 1 2 6\n"),
        5,
        "vertex index 9 is out of range",
    );
    assert_error(
        &format!("f 1 2 3\n{QUAD}f 1 2 50\nf 1 2 6\n"),
        6,
        "vertex index 50",
    );
}

#[test]
fn huge_indices_are_out_of_range_not_a_panic() {
    assert_error(
        &format!("{QUAD}f 1 2 99999999999999999999\n"),
        5,
        "vertex index 99999999999999999999 is out of range: the file has 4 vertices",
    );
    assert_error(
        &format!("{QUAD}f 1 2 18446744073709551615\n"),
        5,
        "is out of range",
    );
    assert_error(
        &format!("{QUAD}f 1 2 4294967296\n"),
        5,
        "vertex index 4294967296 is out of range",
    );
    assert_error(
        &format!("{QUAD}f 1 2 4294967297\n"),
        5,
        "vertex index 4294967297 is out of range",
    );
    assert_error(
        &format!("{QUAD}f 1 2 -99999999999999999999\n"),
        5,
        "relative vertex index",
    );
    assert_error(
        &format!("{QUAD}vt 0 0\nf 1/99999999999999999999 2/1 3/1\n"),
        6,
        "texture coordinate index 99999999999999999999",
    );
    assert_error(
        &format!("{QUAD}t crease 2/1/0 0 99999999999999999999 1\n"),
        5,
        "vertex index 99999999999999999999 is out of range",
    );
    assert_error(
        &format!("{QUAD}t hole 1/0/0 99999999999999999999\n"),
        5,
        "face index 99999999999999999999 is out of range",
    );
    assert_error(
        &format!("{QUAD}t crease 99999999999999999999/1/0 0 1 1\n"),
        5,
        "counts 99999999999999999999/1/0 call for too many values, but the line has 3",
    );
}

#[test]
fn relative_index_before_the_first_vertex_is_an_error() {
    assert_error(
        "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
        3,
        "relative vertex index -3 is out of range: only 2 vertices are defined above this line",
    );
    assert_error(
        &format!("{QUAD}vt 0 0\nf 1/-2 2/-1 3/-1\n"),
        6,
        "relative texture coordinate index -2",
    );
    assert_error(
        &format!("{QUAD}f 1//-1 2//-1 3//-1\n"),
        5,
        "relative normal index -1",
    );
}

#[test]
fn texture_and_normal_indices_out_of_range() {
    assert_error(
        &format!("{QUAD}vt 0 0\nf 1/1 2/2 3/1\n"),
        6,
        "texture coordinate index 2 is out of range: the file has 1 texture coordinates",
    );
    assert_error(
        &format!("{QUAD}f 1//1 2//1 3//1\n"),
        5,
        "normal index 1 is out of range: the file has 0 normals",
    );
    // Defined later is fine.
    let obj = parse(&format!("{QUAD}f 1/1/1 2/1/1 3/1/1\nvt 0 0\nvn 0 0 1\n"));
    assert_eq!(obj.face_texcoords, Some(vec![0, 0, 0]));
    assert_eq!(obj.face_normals, Some(vec![0, 0, 0]));
}

#[test]
fn faces_with_fewer_than_three_vertices() {
    assert_error(
        &format!("{QUAD}f 1 2\n"),
        5,
        "face has 2 vertices; a face needs at least 3",
    );
    assert_error(&format!("{QUAD}f\n"), 5, "face has 0 vertices");
}

/// A face that repeats a vertex is degenerate but legal OBJ, and OpenSubdiv refines it
/// (its regression shapes `catmark_nonman_quadpole*` have such faces): it is read as is,
/// and only strict validation rejects it, naming the face.
#[test]
fn a_vertex_repeated_in_a_face_is_read_and_rejected_only_when_strict() {
    let obj = parse(&format!("{QUAD}f 1 2 3 -2\n"));
    assert_eq!(obj.mesh.face(0), &[0, 1, 2, 2]);
    let err = obj.mesh.check_strict().unwrap_err();
    assert_eq!(err.to_string(), "face 0 lists vertex 2 more than once");
}

/// Mesh errors and warnings told in the file's terms: faces and vertices counted from 1
/// (as `f` statements count vertices), with the line of the face concerned (for a vertex,
/// the first face that uses it).
#[test]
fn mesh_problems_are_described_with_obj_numbering_and_lines() {
    use subsurf::mesh::{MeshError, TopologyWarning};
    let obj = parse(&format!("{QUAD}f 1 2 3 4\nf 1 2 3 -2\n"));
    let e = obj.mesh.check_strict().unwrap_err();
    assert_eq!(
        obj.describe_error(&e),
        (Some(6), "face 2 lists vertex 3 more than once".to_string())
    );
    let w = TopologyWarning::DegenerateFaces { count: 1, first: 1 };
    assert_eq!(
        obj.describe_warning(&w),
        (
            Some(6),
            "1 face(s) (first: face 2) list a vertex more than once; they have no \
             well-defined surface there: refined as degenerate faces, with the vertex sharp \
             where the faces around it cannot be ordered (OpenSubdiv then gives a result that \
             depends on the corner a face starts from); --strict refuses them"
                .to_string()
        )
    );
    // A vertex is located at the first face that uses it; an edge at the first face with it.
    let e = MeshError::NonManifoldVertex {
        vertex: 3,
        faces: 2,
    };
    assert_eq!(
        obj.describe_error(&e),
        (
            Some(5),
            "vertex 4 is non-manifold: its 2 faces do not form a single fan".to_string()
        )
    );
    let w = TopologyWarning::NonManifoldEdges {
        count: 1,
        first: (2, 1),
    };
    assert_eq!(obj.describe_warning(&w).0, Some(5));
    assert!(obj.describe_warning(&w).1.contains("(first: 3-2)"));
    // Errors about no element of the file keep the library's text.
    let e = MeshError::BadFaceOffsets("x".into());
    assert_eq!(obj.describe_error(&e), (None, e.to_string()));
}

/// Coordinates beyond 1e75 in magnitude are refused at their `v` line, in `{:e}` form.
#[test]
fn coordinates_beyond_1e75_are_refused_at_their_line() {
    assert_error(
        "v 0 0 0\nv 0 -1e100 0\n",
        2,
        "v: the coordinate -1e100 is too large; coordinates must be below 1e75 in magnitude",
    );
    assert_error("v 1.5e308 0 0\n", 1, "the coordinate 1.5e308 is too large");
    // "Below 1e75": 1e75 itself is refused, the largest double below it accepted.
    assert_error(
        "v 0 0 0\nv 1e75 0 0\n",
        2,
        "the coordinate 1e75 is too large",
    );
    assert_error("v 0 -1e75 0\n", 1, "the coordinate -1e75 is too large");
    let below = f64::from_bits(1e75f64.to_bits() - 1);
    let obj = parse(&format!("v {below} -{below} 0\n"));
    assert_eq!(obj.mesh.positions()[0], [below, -below, 0.0]);
    let e = PolyMesh::from_faces(vec![[0.0; 3], [1e75, 0.0, 0.0], [0.0; 3]], &[[0, 1, 2]]);
    assert!(e.unwrap_err().to_string().contains("must be below 1e75"));
}

#[test]
fn malformed_index_tokens() {
    let cases = [
        "1/2/3/4", "1//", "/1", "1/", "a", "1/a", "1//b", "1/1/", "1.5", "--1", "+-1", "1e3",
    ];
    for tok in cases {
        let text = format!("{QUAD}vt 0 0\nvt 0 1\nvn 0 0 1\nf 1 2 {tok}\n");
        assert_error(&text, 8, &format!("malformed vertex reference '{tok}'"));
    }
    assert_error(
        &format!("{QUAD}f 1 2 3 //1\n"),
        5,
        "malformed vertex reference '//1'",
    );
}

#[test]
fn non_utf8_lines() {
    let e = assert_error_bytes(
        b"v 0 0 0\nv 1 0 0\ng caf\xe9\nv 0 1 0\n",
        3,
        "line 3 is not valid UTF-8",
    );
    assert_eq!(e.to_string(), "test.obj:3: line 3 is not valid UTF-8");
    // Even in a comment.
    assert_error_bytes(b"# \xff\xfe\n", 1, "not valid UTF-8");
    // In the second physical line of a continued line: that line is named.
    assert_error_bytes(b"v 0 0 \\\n\xff\n", 2, "line 2 is not valid UTF-8");
}

#[test]
fn binary_garbage_fails_on_the_first_line() {
    // A gzip header: its first byte is a control character.
    assert_error_bytes(
        b"\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03\xed\xbd\n",
        1,
        "line 1 contains the control character 0x1f",
    );
    // ASCII control characters.
    assert_error_bytes(b"\x7fELF\x02\x01\x01\x00\n", 1, "(is this a binary file?)");
    // Invalid UTF-8 right away.
    assert_error_bytes(&[0xff, 0x00, 0x13, 0x80, 0x7f], 1, "not valid UTF-8");
    // Pseudo-random bytes, with and without newlines: an error, never a panic.
    let mut x: u64 = 0x1234_5678_9abc_def0;
    let mut garbage = Vec::with_capacity(1 << 20);
    for _ in 0..(1 << 20) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        garbage.push((x >> 24) as u8);
    }
    let e = parse_obj(&garbage, NAME).unwrap_err();
    assert_eq!(e.line, Some(1));
    // Text that is not OBJ: the first line that does not start with a keyword.
    assert_error(
        "{\"vertices\": [1, 2, 3]}\n",
        1,
        "is not an OBJ statement (is this an OBJ file?)",
    );
    assert_error(
        "ply\nformat ascii 1.0\nend_header\n0 0 0\n",
        4,
        "'0' is not an OBJ statement",
    );
    let long = "a".repeat(10_000);
    assert_error(
        &long,
        1,
        &format!("'{}...' is not an OBJ statement", "a".repeat(32)),
    );
    // Valid ASCII but not OBJ.
    assert_error("v 1 2 3\nv\u{0}\u{1}\n", 2, "control character 0x00");
}

#[test]
fn never_panics_on_mutations_of_a_valid_file() {
    let base = format!(
        "{QUAD}vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 -2/1/1 4/1/-1\nt crease 3/2/0 0 1 2 1 2\nt corner 1/1/0 3 2\n\
         t hole 1/0/0 0\nt interpolateboundary 1/0/0 1\nt creasemethod 0/0/1 chaikin\n"
    );
    let bytes = base.as_bytes();
    let alphabet = b" /\\-+#0159.tefvn\n\r\x00\xffxe";
    for i in 0..bytes.len() {
        for &c in alphabet {
            let mut m = bytes.to_vec();
            m[i] = c;
            let _ = parse_obj(&m, NAME);
            m.remove(i);
            let _ = parse_obj(&m, NAME);
        }
        let _ = parse_obj(&bytes[..i], NAME);
    }
}

#[test]
fn tag_errors() {
    let q = format!("{QUAD}f 1 2 3 4\n");
    let at = 6;
    assert_error(
        &format!("{q}t crease 2-1-0 0 1 1\n"),
        at,
        "malformed counts '2-1-0'",
    );
    assert_error(
        &format!("{q}t crease 2/1 0 1 1\n"),
        at,
        "malformed counts '2/1'",
    );
    assert_error(
        &format!("{q}t crease 2/1/0/0 0 1 1\n"),
        at,
        "malformed counts",
    );
    assert_error(
        &format!("{q}t crease 2/x/0 0 1 1\n"),
        at,
        "malformed counts",
    );
    assert_error(&format!("{q}t crease\n"), at, "missing counts");
    assert_error(&format!("{q}t\n"), at, "missing tag name");
    assert_error(
        &format!("{q}t crease 2/1/0 0 1\n"),
        at,
        "counts 2/1/0 call for 3 values, but the line has 2",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 1 1 1\n"),
        at,
        "call for 3 values, but the line has 4",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 1.5 1\n"),
        at,
        "'1.5' is not an integer index",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 -1 1\n"),
        at,
        "negative index -1",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 4 1\n"),
        at,
        "t crease: vertex index 4 is out of range: the file has 4 vertices",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 1 nan\n"),
        at,
        "sharpness must be a number ≥ 0",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 1 -1\n"),
        at,
        "sharpness must be a number ≥ 0",
    );
    assert_error(
        &format!("{q}t crease 2/1/0 0 1 sharp\n"),
        at,
        "sharpness 'sharp' is not a number",
    );
    assert_error(
        &format!("{q}t crease 1/1/0 0 1\n"),
        at,
        "unexpected counts 1/1/0",
    );
    assert_error(
        &format!("{q}t crease 3/2/1 0 1 2 1 1 x\n"),
        at,
        "unexpected counts 3/2/1",
    );
    assert_error(
        &format!("{q}t crease 4/2/0 0 1 2 3 1 1\n"),
        at,
        "unexpected counts 4/2/0",
    );
    assert_error(
        &format!("{q}t corner 0/0/0\n"),
        at,
        "unexpected counts 0/0/0",
    );
    assert_error(
        &format!("{q}t corner 2/3/0 0 1 1 1 1\n"),
        at,
        "unexpected counts 2/3/0",
    );
    assert_error(
        &format!("{q}t corner 1/1/0 9 1\n"),
        at,
        "t corner: vertex index 9 is out of range",
    );
    assert_error(
        &format!("{q}t corner 1/1/0 0 -0.5\n"),
        at,
        "sharpness must be a number ≥ 0",
    );
    assert_error(
        &format!("{q}t hole 1/0/0 1\n"),
        at,
        "t hole: face index 1 is out of range: the file has 1 faces",
    );
    assert_error(&format!("{q}t hole 1/0/0 -1\n"), at, "negative index -1");
    assert_error(
        &format!("{q}t hole 1/1/0 0 1\n"),
        at,
        "unexpected counts 1/1/0",
    );
    assert_error(
        &format!("{q}t interpolateboundary 1/0/0 3\n"),
        at,
        "unknown value 3",
    );
    assert_error(
        &format!("{q}t interpolateboundary 1/0/0 x\n"),
        at,
        "'x' is not an integer",
    );
    assert_error(
        &format!("{q}t interpolateboundary 0/0/1 edge\n"),
        at,
        "unexpected counts 0/0/1",
    );
    assert_error(
        &format!("{q}t creasemethod 0/0/1 sharp\n"),
        at,
        "unknown crease method 'sharp'",
    );
    assert_error(
        &format!("{q}t smoothtriangles 0/0/1 loop\n"),
        at,
        "unknown triangle rule 'loop'",
    );
    assert_error(
        &format!("{q}t smoothtriangles 0/0/0\n"),
        at,
        "unexpected counts 0/0/0",
    );
}

#[test]
fn deferred_errors_report_the_earliest_line() {
    // A tag on line 5 and a face on line 6 are both out of range: line 5 is reported.
    assert_error(
        &format!("{QUAD}t crease 2/1/0 0 8 1\nf 1 2 9\n"),
        5,
        "t crease",
    );
    assert_error(
        &format!("{QUAD}f 1 2 9\nt crease 2/1/0 0 8 1\n"),
        5,
        "f: vertex index 9",
    );
}

#[test]
fn read_obj_names_the_file_and_reports_os_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cube.obj");
    std::fs::write(&path, format!("{QUAD}f 1 2 3 4\n")).unwrap();
    let obj = read_obj(&path).unwrap();
    assert_eq!(obj.mesh.num_faces(), 1);

    std::fs::write(&path, "v 1 2\n").unwrap();
    let e = read_obj(&path).unwrap_err();
    assert_eq!(e.source_name, path.display().to_string());
    assert!(e
        .to_string()
        .starts_with(&format!("{}:1: ", path.display())));

    let missing = dir.path().join("missing.obj");
    let e = read_obj(&missing).unwrap_err();
    assert_eq!(e.line, None);
    assert!(
        e.message
            .starts_with(&format!("cannot read {}: ", missing.display())),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------

fn write_to_string(mesh: &PolyMesh, opts: &WriteOptions) -> String {
    let mut out = Vec::new();
    write_obj(&mut out, mesh, opts).unwrap();
    String::from_utf8(out).unwrap()
}

fn tagged_mesh() -> PolyMesh {
    let p = vec![
        [0.1, 0.2, 0.3],
        [1.0 / 3.0, -0.0, 1e-300],
        // The largest coordinate accepted: the double just below 1e75.
        [
            f64::from_bits(1e75_f64.to_bits() - 1),
            f64::MIN_POSITIVE,
            -2.5,
        ],
        [-9.876_543_210_987_654e74, f64::EPSILON, 5e-324],
        [std::f64::consts::PI, -1e-7, 123_456_789.123_456_79],
    ];
    let mut m = PolyMesh::from_faces(p, &[vec![0, 1, 2, 3], vec![0, 3, 4]]).unwrap();
    m.tags.creases = vec![crease(0, 1, 0.1), crease(1, 2, 10.0), crease(2, 3, 2.75)];
    m.tags.corners = vec![Corner {
        vertex: 4,
        sharpness: 1.0 / 3.0,
    }];
    m.tags.holes = vec![1];
    m
}

#[test]
fn written_file_layout() {
    let m = PolyMesh::from_faces(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [-0.0, 0.5, 0.25],
        ],
        &[vec![0, 1, 2, 3]],
    )
    .unwrap();
    let mut m = m;
    m.tags.creases.push(crease(0, 1, 1.5));
    m.tags.corners.push(Corner {
        vertex: 2,
        sharpness: 10.0,
    });
    m.tags.holes.push(0);
    let opts = WriteOptions {
        comment: Some("subsurf subdivide -l 1 in.obj"),
        scheme: Some(Options {
            boundary: BoundaryInterpolation::EdgeAndCorner,
            crease_method: CreaseMethod::Chaikin,
            triangles: TriangleSubdivision::Smooth,
            ..Options::default()
        }),
        normals: None,
    };
    let text = write_to_string(&m, &opts);
    let expected = format!(
        "# written by subsurf {}\n\
         # subsurf subdivide -l 1 in.obj\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv -0 0.5 0.25\n\
         f 1 2 3 4\n\
         t interpolateboundary 1/0/0 1\n\
         t creasemethod 0/0/1 chaikin\n\
         t smoothtriangles 0/0/1 smooth\n\
         t crease 2/1/0 0 1 1.5\n\
         t corner 1/1/0 2 10\n\
         t hole 1/0/0 0\n",
        env!("CARGO_PKG_VERSION")
    );
    assert_eq!(text, expected);
}

#[test]
fn default_scheme_writes_only_interpolateboundary() {
    let m = PolyMesh::from_faces(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    )
    .unwrap();
    let text = write_to_string(
        &m,
        &WriteOptions {
            scheme: Some(Options::default()),
            ..Default::default()
        },
    );
    assert!(text.contains("t interpolateboundary 1/0/0 2\n"));
    assert!(!text.contains("creasemethod"));
    assert!(!text.contains("smoothtriangles"));
    let text = write_to_string(&m, &WriteOptions::default());
    assert!(!text.contains("t "));
}

#[test]
fn normals_are_written_per_vertex() {
    let m = PolyMesh::from_faces(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    )
    .unwrap();
    let normals = [[0.0, 0.0, 1.0]; 3];
    let text = write_to_string(
        &m,
        &WriteOptions {
            normals: Some(&normals),
            ..Default::default()
        },
    );
    assert!(
        text.contains("vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nf 1//1 2//2 3//3\n"),
        "{text}"
    );
    let obj = parse(&text);
    assert_eq!(obj.normals, normals.to_vec());
    assert_eq!(obj.face_normals, Some(vec![0, 1, 2]));

    let short = [[0.0, 0.0, 1.0]; 2];
    let mut out = Vec::new();
    let e = write_obj(
        &mut out,
        &m,
        &WriteOptions {
            normals: Some(&short),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert_eq!(e.kind(), io::ErrorKind::InvalidInput);
    let bad = [[0.0, 0.0, 1.0], [f64::NAN, 0.0, 0.0], [0.0, 0.0, 1.0]];
    let e = write_obj(
        &mut out,
        &m,
        &WriteOptions {
            normals: Some(&bad),
            ..Default::default()
        },
    )
    .unwrap_err();
    assert_eq!(e.kind(), io::ErrorKind::InvalidData);
}

#[test]
fn writer_refuses_non_finite_positions() {
    let mut m = PolyMesh::from_faces(
        vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    )
    .unwrap();
    m.positions_mut()[1][2] = f64::INFINITY;
    let e = write_obj(&mut Vec::new(), &m, &WriteOptions::default()).unwrap_err();
    assert_eq!(e.kind(), io::ErrorKind::InvalidData);
    assert!(e.to_string().contains("vertex 1"), "{e}");
}

#[test]
fn round_trip_is_bit_exact() {
    let m = tagged_mesh();
    let scheme = Options {
        boundary: BoundaryInterpolation::None,
        crease_method: CreaseMethod::Chaikin,
        triangles: TriangleSubdivision::Catmark,
        ..Options::default()
    };
    let text = write_to_string(
        &m,
        &WriteOptions {
            scheme: Some(scheme),
            comment: Some("two\nlines"),
            normals: None,
        },
    );
    assert!(
        !text.contains('e') || !text.lines().any(|l| l.starts_with("v ") && l.contains('e')),
        "exponent form"
    );
    let obj = parse(&text);
    let bits = |m: &PolyMesh| -> Vec<u64> {
        m.positions()
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect()
    };
    assert_eq!(bits(&obj.mesh), bits(&m));
    assert_eq!(
        faces(&obj),
        m.faces().map(<[u32]>::to_vec).collect::<Vec<_>>()
    );
    assert_eq!(obj.mesh.tags, m.tags);
    let sharp_bits: Vec<u32> = obj
        .mesh
        .tags
        .creases
        .iter()
        .map(|c| c.sharpness.to_bits())
        .collect();
    assert_eq!(
        sharp_bits,
        m.tags
            .creases
            .iter()
            .map(|c| c.sharpness.to_bits())
            .collect::<Vec<_>>()
    );
    assert_eq!(obj.options.resolve(Options::default()), scheme);
    assert!(obj.unsupported_tags.is_empty());
}

#[test]
fn many_holes_are_split_over_lines() {
    let n = 2500u32;
    let mut p = Vec::new();
    let mut f = Vec::new();
    for i in 0..n {
        let x = f64::from(i);
        p.extend([[x, 0.0, 0.0], [x + 0.5, 0.0, 0.0], [x, 1.0, 0.0]]);
        f.push(vec![3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let mut m = PolyMesh::from_faces(p, &f).unwrap();
    m.tags.holes = (0..n).collect();
    let text = write_to_string(&m, &WriteOptions::default());
    let hole_lines: Vec<&str> = text.lines().filter(|l| l.starts_with("t hole ")).collect();
    assert_eq!(hole_lines.len(), 3);
    assert!(hole_lines[0].starts_with("t hole 1000/0/0 0 1 2 "));
    assert!(hole_lines[2].starts_with("t hole 500/0/0 2000 "));
    assert_eq!(parse(&text).mesh.tags.holes, m.tags.holes);
}

#[test]
fn random_positions_round_trip_bit_exactly() {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut p = Vec::new();
    while p.len() < 3000 {
        let mut v = [0.0; 3];
        for c in &mut v {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let f = f64::from_bits(x);
            // Every finite value up to the mesh layer's limit on coordinates.
            *c = if f.is_finite() && f.abs() < subsurf::mesh::MAX_COORDINATE {
                f
            } else {
                0.5
            };
        }
        p.push(v);
    }
    let faces: Vec<[u32; 3]> = (0..1000).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    let m = PolyMesh::from_faces(p, &faces).unwrap();
    let obj = parse(&write_to_string(&m, &WriteOptions::default()));
    for (a, b) in obj
        .mesh
        .positions()
        .iter()
        .flatten()
        .zip(m.positions().iter().flatten())
    {
        assert_eq!(a.to_bits(), b.to_bits());
    }
}

// ---------------------------------------------------------------------------------------
// Atomic writes
// ---------------------------------------------------------------------------------------

fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn atomic_write_creates_and_replaces_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    write_atomically(&path, |w| {
        use std::io::Write;
        w.write_all(b"first\n")
    })
    .unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "first\n");
    write_atomically(&path, |w| {
        use std::io::Write;
        w.write_all(b"second\n")
    })
    .unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "second\n");
    assert_eq!(dir_entries(dir.path()), vec!["out.obj"]);
}

#[test]
fn atomic_write_leaves_nothing_on_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    let e = write_atomically(&path, |w| {
        use std::io::Write;
        w.write_all(b"partial")?;
        Err(io::Error::other("boom"))
    })
    .unwrap_err();
    assert_eq!(e.to_string(), "boom");
    assert!(!path.exists());
    assert!(
        dir_entries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );

    // An existing file keeps its old contents.
    std::fs::write(&path, "old").unwrap();
    let _ = write_atomically(&path, |_| Err(io::Error::other("boom"))).unwrap_err();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
    assert_eq!(dir_entries(dir.path()), vec!["out.obj"]);
}

#[test]
fn atomic_write_cleans_up_after_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.obj");
    let result = std::panic::catch_unwind(|| {
        let _ = write_atomically(&path, |_| panic!("writer panicked"));
    });
    assert!(result.is_err());
    assert!(dir_entries(dir.path()).is_empty());
}

#[test]
fn atomic_write_into_a_missing_directory_fails() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("no").join("such").join("out.obj");
    let e = write_atomically(&path, |_| Ok(())).unwrap_err();
    assert_eq!(e.kind(), io::ErrorKind::NotFound);
    assert!(!dir.path().join("no").exists());
}

#[test]
fn atomic_write_of_an_obj_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mesh.obj");
    let m = tagged_mesh();
    write_atomically(&path, |w| write_obj(w, &m, &WriteOptions::default())).unwrap();
    let obj = read_obj(&path).unwrap();
    assert_eq!(obj.mesh.positions(), m.positions());
    assert_eq!(obj.mesh.tags, m.tags);
    assert_eq!(dir_entries(dir.path()), vec!["mesh.obj"]);
}
