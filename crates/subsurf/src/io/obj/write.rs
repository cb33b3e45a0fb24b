//! The OBJ writer.

use super::WriteOptions;
use crate::io::push_decimal;
use crate::mesh::{
    CreaseMethod, FaceVaryingInterpolation, GroupState, Options, PolyMesh, TriangleSubdivision,
};
use std::io::{self, Write};

/// Bytes gathered before handing them to the writer.
const CHUNK: usize = 1 << 16;

/// Holes per `t hole` line.
const HOLES_PER_LINE: usize = 1000;

/// Writes `mesh` (with its tags) as OBJ.
///
/// The output is: a header comment (`# written by subsurf VERSION`, then `opts.comment`),
/// the `mtllib` lines of [`PolyMesh::groups`], `v x y z` per vertex, `vn x y z` per vertex when `opts.normals` is given, `vt` per value
/// of the face-varying channel named `"uv"` (other channels are not written), one `f` line per
/// face (1-based, `f a//a b//b ...` with normals, `f a/t b/u ...` or `f a/t/a ...` with
/// texture coordinates), then the tags: `t interpolateboundary`
/// (and `t creasemethod 0/0/1 chaikin`, `t smoothtriangles 0/0/1 smooth`,
/// `t facevaryinginterpolateboundary 1/0/0 K` when they differ from the defaults) when
/// `opts.scheme` is given, one `t crease 2/1/0` per crease, one
/// `t corner 1/1/0` per corner, `t hole N/0/0` lines of up to 1000 faces, and the knot tags
/// of [`PolyMesh::knots`] (`t interval`, `t sideinterval`, `t weight`; see `super`).
/// Before a face whose [`GroupState`] differs from the previous face's, each part that
/// changes is written: `o NAME`, `g NAME...`, `usemtl NAME` (a part that changes back to
/// none, which no file read gives, as `o default`, `g default`, `usemtl default`); a mesh
/// without groups gets none of these lines.
///
/// Coordinates are printed as the shortest decimals that read back as the same `f64`,
/// never in exponent form ([`push_decimal`]), sharpness with Rust's shortest round-trip
/// representation of `f32`: reading the file back gives bit-identical values. Output goes to `w` in chunks of 64 KiB or more (the `v` and `vn`
/// lines of large meshes are formatted in parallel on the current rayon pool, in blocks
/// of 4096 points, and written in order); wrap `w` in a
/// [`BufWriter`](std::io::BufWriter) only if small writes are expensive anyway.
///
/// # Errors
/// Errors of `w`; [`io::ErrorKind::InvalidInput`] when `opts.normals` does not have one
/// normal per vertex; [`io::ErrorKind::InvalidData`] for a non-finite coordinate or normal
/// (possible after [`PolyMesh::positions_mut`]) or a NaN or negative sharpness, which would
/// not read back.
pub fn write_obj<W: std::io::Write>(
    w: &mut W,
    mesh: &PolyMesh,
    opts: &WriteOptions,
) -> std::io::Result<()> {
    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK + 4096);
    write_header(&mut buf, opts.comment)?;
    for lib in &mesh.groups.material_libraries {
        push_statement(&mut buf, "mtllib", lib);
    }
    write_points(&mut buf, w, mesh, opts.normals)?;
    let uv = mesh.face_varying.iter().find(|c| c.name() == "uv");
    if let Some(uv) = uv {
        uv.validate(mesh.face_offsets())
            .map_err(|e| invalid_data(e.to_string()))?;
        for t in uv.values().chunks_exact(uv.dim()) {
            buf.extend_from_slice(b"vt");
            for &x in t {
                buf.push(b' ');
                push_decimal(&mut buf, x);
            }
            buf.push(b'\n');
            flush(&mut buf, w, false)?;
        }
    }
    write_faces(
        &mut buf,
        w,
        mesh,
        uv.map(|c| c.indices()),
        opts.normals.is_some(),
    )?;
    if let Some(scheme) = opts.scheme {
        write_scheme(&mut buf, &scheme)?;
    }
    write_sharp_and_holes(&mut buf, w, mesh)?;
    write_knots(&mut buf, w, mesh)?;
    flush(&mut buf, w, true)
}

/// The header comment: `# written by subsurf VERSION`, then each line of `comment` (its
/// control characters replaced by spaces, which would make a line unreadable or continue
/// it).
fn write_header(buf: &mut Vec<u8>, comment: Option<&str>) -> io::Result<()> {
    writeln!(buf, "# written by subsurf {}", env!("CARGO_PKG_VERSION"))?;
    for line in comment.into_iter().flat_map(str::lines) {
        buf.extend_from_slice(b"# ");
        let clean: String = line
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        buf.extend_from_slice(clean.as_bytes());
        buf.push(b'\n');
    }
    Ok(())
}

/// The `v` lines, and the `vn` lines of `normals` when given, after checking that every
/// coordinate is finite and that there is one normal per vertex.
fn write_points<W: Write>(
    buf: &mut Vec<u8>,
    w: &mut W,
    mesh: &PolyMesh,
    normals: Option<&[[f64; 3]]>,
) -> io::Result<()> {
    if let Some(i) = first_non_finite(mesh.positions()) {
        let p = mesh.positions()[i];
        return Err(invalid_data(format!(
            "vertex {i} has a non-finite coordinate ({}, {}, {})",
            p[0], p[1], p[2]
        )));
    }
    write_triples(buf, w, b"v ", mesh.positions())?;
    let Some(normals) = normals else {
        return Ok(());
    };
    if normals.len() != mesh.num_vertices() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{} normals given for {} vertices; OBJ output needs one per vertex",
                normals.len(),
                mesh.num_vertices()
            ),
        ));
    }
    if let Some(i) = first_non_finite(normals) {
        let n = normals[i];
        return Err(invalid_data(format!(
            "the normal of vertex {i} is not finite ({}, {}, {})",
            n[0], n[1], n[2]
        )));
    }
    write_triples(buf, w, b"vn ", normals)
}

/// One `f` line per face, 1-based: `f a b ...`, with texture coordinates `uv_indices`
/// `f a/t b/u ...`, with normals `f a//a ...` or `f a/t/a ...`.
fn write_faces<W: Write>(
    buf: &mut Vec<u8>,
    w: &mut W,
    mesh: &PolyMesh,
    uv_indices: Option<&[u32]>,
    with_normals: bool,
) -> io::Result<()> {
    let none = GroupState::default();
    let mut last = &none;
    for (f, (face, &start)) in mesh.faces().zip(mesh.face_offsets()).enumerate() {
        if let Some(state) = mesh.groups.state(f) {
            write_state_change(buf, last, state);
            last = state;
        }
        buf.push(b'f');
        for (k, &v) in face.iter().enumerate() {
            let v = u64::from(v) + 1;
            buf.push(b' ');
            push_u64(buf, v);
            if let Some(t) = uv_indices {
                buf.push(b'/');
                push_u64(buf, u64::from(t[start as usize + k]) + 1);
            }
            if with_normals {
                buf.extend_from_slice(if uv_indices.is_some() { b"/" } else { b"//" });
                push_u64(buf, v);
            }
        }
        buf.push(b'\n');
        flush(buf, w, false)?;
    }
    Ok(())
}

/// The `o`, `g` and `usemtl` lines that take the faces from state `last` to `state`.
fn write_state_change(buf: &mut Vec<u8>, last: &GroupState, state: &GroupState) {
    let parts = [
        ("o", &last.object, &state.object),
        ("g", &last.group, &state.group),
        ("usemtl", &last.material, &state.material),
    ];
    for (keyword, before, now) in parts {
        if before != now {
            push_statement(buf, keyword, now.as_deref().unwrap_or("default"));
        }
    }
}

/// `keyword text` (`keyword` alone for an empty text) and a line end, control characters
/// in `text` (which would end or continue the line) replaced by spaces.
fn push_statement(buf: &mut Vec<u8>, keyword: &str, text: &str) {
    buf.extend_from_slice(keyword.as_bytes());
    if let Some(t) = Some(text).filter(|t| !t.is_empty()) {
        buf.push(b' ');
        let clean: String = t
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        buf.extend_from_slice(clean.trim_end_matches('\\').as_bytes());
    }
    buf.push(b'\n');
}

/// The scheme's tags: `t interpolateboundary`, and `t creasemethod`, `t smoothtriangles`,
/// `t facevaryinginterpolateboundary` when they differ from the defaults.
fn write_scheme(buf: &mut Vec<u8>, scheme: &Options) -> io::Result<()> {
    writeln!(
        buf,
        "t interpolateboundary 1/0/0 {}",
        scheme.boundary.tag_value()
    )?;
    if scheme.crease_method == CreaseMethod::Chaikin {
        buf.extend_from_slice(b"t creasemethod 0/0/1 chaikin\n");
    }
    if scheme.triangles == TriangleSubdivision::Smooth {
        buf.extend_from_slice(b"t smoothtriangles 0/0/1 smooth\n");
    }
    if scheme.face_varying != FaceVaryingInterpolation::default() {
        writeln!(
            buf,
            "t facevaryinginterpolateboundary 1/0/0 {}",
            scheme.face_varying.tag_value()
        )?;
    }
    Ok(())
}

/// One `t crease 2/1/0` per crease, one `t corner 1/1/0` per corner (after checking their
/// sharpness reads back), `t hole N/0/0` lines of up to [`HOLES_PER_LINE`] faces.
fn write_sharp_and_holes<W: Write>(
    buf: &mut Vec<u8>,
    w: &mut W,
    mesh: &PolyMesh,
) -> io::Result<()> {
    for c in &mesh.tags.creases {
        check_sharpness(c.sharpness, || {
            format!("the crease on edge ({}, {})", c.v0, c.v1)
        })?;
        writeln!(buf, "t crease 2/1/0 {} {} {}", c.v0, c.v1, c.sharpness)?;
        flush(buf, w, false)?;
    }
    for c in &mesh.tags.corners {
        check_sharpness(c.sharpness, || format!("the corner at vertex {}", c.vertex))?;
        writeln!(buf, "t corner 1/1/0 {} {}", c.vertex, c.sharpness)?;
        flush(buf, w, false)?;
    }
    for chunk in mesh.tags.holes.chunks(HOLES_PER_LINE) {
        write!(buf, "t hole {}/0/0", chunk.len())?;
        for &f in chunk {
            buf.push(b' ');
            push_u64(buf, u64::from(f));
        }
        buf.push(b'\n');
        flush(buf, w, false)?;
    }
    Ok(())
}

/// The knot tags of [`PolyMesh::knots`]: `t interval 2/1/0 a b d`, `t sideinterval 3/1/0 f a
/// b d`, `t weight 1/1/0 v w`, values as shortest round-trip `f64`.
fn write_knots<W: Write>(buf: &mut Vec<u8>, w: &mut W, mesh: &PolyMesh) -> io::Result<()> {
    let check = |value: f64, positive: bool, what: &dyn Fn() -> String| {
        let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
        if ok {
            Ok(())
        } else {
            Err(invalid_data(format!(
                "{} is {value}; it must be a finite number {}",
                what(),
                if positive { "> 0" } else { "≥ 0" }
            )))
        }
    };
    let k = &mesh.knots;
    for t in &k.intervals {
        check(t.interval, false, &|| {
            format!("the knot interval of edge ({}, {})", t.v0, t.v1)
        })?;
        writeln!(buf, "t interval 2/1/0 {} {} {}", t.v0, t.v1, t.interval)?;
        flush(buf, w, false)?;
    }
    for t in &k.side_intervals {
        check(t.interval, false, &|| {
            format!(
                "the side interval of edge ({}, {}) in face {}",
                t.v0, t.v1, t.face
            )
        })?;
        writeln!(
            buf,
            "t sideinterval 3/1/0 {} {} {} {}",
            t.face, t.v0, t.v1, t.interval
        )?;
        flush(buf, w, false)?;
    }
    for t in &k.weights {
        check(t.weight, true, &|| {
            format!("the weight of vertex {}", t.vertex)
        })?;
        writeln!(buf, "t weight 1/1/0 {} {}", t.vertex, t.weight)?;
        flush(buf, w, false)?;
    }
    Ok(())
}

fn invalid_data(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

fn check_sharpness(s: f32, what: impl FnOnce() -> String) -> io::Result<()> {
    if s.is_nan() || s < 0.0 {
        return Err(invalid_data(format!(
            "{} has sharpness {s}; it must be ≥ 0",
            what()
        )));
    }
    Ok(())
}

/// The first point with a coordinate that is not finite.
fn first_non_finite(points: &[[f64; 3]]) -> Option<usize> {
    points.iter().position(|p| !p.iter().all(|c| c.is_finite()))
}

/// Points per block of [`write_triples`] formatted by one task.
const POINTS_PER_BLOCK: usize = 4096;

/// Blocks formatted at once by [`write_triples`] before they are written: enough to keep
/// a few threads busy, about 2 MB of text.
const BLOCKS_PER_BATCH: usize = 8;

/// `prefix x y z\n` for each point, in order, after what `buf` holds.
///
/// Formatting shortest round-trip `f64`s is most of the time of writing a refined mesh,
/// so blocks of [`POINTS_PER_BLOCK`] points are formatted in parallel on the current rayon
/// pool, a batch of [`BLOCKS_PER_BATCH`] at a time into buffers kept from batch to batch,
/// and written in order: the text is the same as one thread's.
fn write_triples<W: Write>(
    buf: &mut Vec<u8>,
    w: &mut W,
    prefix: &[u8],
    points: &[[f64; 3]],
) -> io::Result<()> {
    use rayon::prelude::*;
    if points.len() <= POINTS_PER_BLOCK || rayon::current_num_threads() == 1 {
        for p in points {
            write_triple(buf, prefix, p);
            flush(buf, w, false)?;
        }
        return Ok(());
    }
    flush(buf, w, true)?;
    let mut texts = vec![Vec::new(); BLOCKS_PER_BATCH];
    for batch in points.chunks(POINTS_PER_BLOCK * BLOCKS_PER_BATCH) {
        let blocks = batch.chunks(POINTS_PER_BLOCK);
        let texts = &mut texts[..blocks.len()];
        (texts.par_iter_mut().zip(blocks.collect::<Vec<_>>())).for_each(|(text, block)| {
            text.clear();
            for p in block {
                write_triple(text, prefix, p);
            }
        });
        for text in texts.iter() {
            w.write_all(text)?;
        }
    }
    Ok(())
}

/// `prefix x y z\n` with [`push_decimal`].
fn write_triple(buf: &mut Vec<u8>, prefix: &[u8], p: &[f64; 3]) {
    buf.extend_from_slice(prefix);
    push_decimal(buf, p[0]);
    buf.push(b' ');
    push_decimal(buf, p[1]);
    buf.push(b' ');
    push_decimal(buf, p[2]);
    buf.push(b'\n');
}

/// Decimal digits of `n`, without allocating.
fn push_u64(buf: &mut Vec<u8>, mut n: u64) {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    buf.extend_from_slice(&digits[i..]);
}

/// Hands `buf` to `w` once it holds a chunk (or always when `force`).
fn flush<W: Write>(buf: &mut Vec<u8>, w: &mut W, force: bool) -> io::Result<()> {
    if force || buf.len() >= CHUNK {
        w.write_all(buf)?;
        buf.clear();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vertex and normal lines formatted in parallel are the text one thread writes, and
    /// read back bit for bit.
    #[test]
    fn parallel_formatting_writes_the_same_text() {
        let n = 3 * POINTS_PER_BLOCK * BLOCKS_PER_BATCH + 17;
        let positions: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let x = i as f64;
                [(0.37 * x).sin() * 1e3, 1.0 / (1.0 + x), -x * 1e-9]
            })
            .collect();
        let faces: Vec<[u32; 3]> = (0..n as u32 - 2).map(|i| [i, i + 1, i + 2]).collect();
        let mesh = PolyMesh::from_faces(positions, &faces).unwrap();
        let normals: Vec<[f64; 3]> = mesh
            .positions()
            .iter()
            .map(|p| [p[1], p[2], p[0]])
            .collect();
        let opts = WriteOptions {
            normals: Some(&normals),
            scheme: None,
            comment: Some("test"),
        };
        let text = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = Vec::new();
            pool.install(|| write_obj(&mut out, &mesh, &opts)).unwrap();
            out
        };
        let (one, three) = (text(1), text(3));
        assert!(one == three, "the texts differ");
        let back = super::super::parse_obj(&three, "t.obj").unwrap();
        assert_eq!(back.mesh.positions(), mesh.positions());
    }
}
