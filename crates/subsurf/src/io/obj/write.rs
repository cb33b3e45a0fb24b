//! The OBJ writer.

use super::WriteOptions;
use crate::mesh::{CreaseMethod, PolyMesh, TriangleSubdivision};
use std::io::{self, Write};

/// Bytes gathered before handing them to the writer.
const CHUNK: usize = 1 << 16;

/// Holes per `t hole` line.
const HOLES_PER_LINE: usize = 1000;

/// Writes `mesh` (with its tags) as OBJ.
///
/// The output is: a header comment (`# written by subsurf VERSION`, then `opts.comment`),
/// `v x y z` per vertex, `vn x y z` per vertex when `opts.normals` is given, one `f` line per
/// face (1-based, `f a//a b//b ...` with normals), then the tags: `t interpolateboundary`
/// (and `t creasemethod 0/0/1 chaikin`, `t smoothtriangles 0/0/1 smooth` when they differ
/// from the defaults) when `opts.scheme` is given, one `t crease 2/1/0` per crease, one
/// `t corner 1/1/0` per corner, `t hole N/0/0` lines of up to 1000 faces, and the knot tags
/// of [`PolyMesh::knots`] (`t interval`, `t sideinterval`, `t weight`; see [`super`]).
///
/// Coordinates are printed with Rust's shortest round-trip representation of `f64` (never
/// in exponent form), sharpness with that of `f32`: reading the file back gives
/// bit-identical values. Output goes to `w` in chunks of 64 KiB; wrap it in a
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

    writeln!(buf, "# written by subsurf {}", env!("CARGO_PKG_VERSION"))?;
    if let Some(comment) = opts.comment {
        for line in comment.lines() {
            buf.extend_from_slice(b"# ");
            // Control characters would make the line unreadable (or continue it).
            let clean: String = line
                .chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect();
            buf.extend_from_slice(clean.as_bytes());
            buf.push(b'\n');
        }
    }

    for (i, p) in mesh.positions().iter().enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(invalid_data(format!(
                "vertex {i} has a non-finite coordinate ({}, {}, {})",
                p[0], p[1], p[2]
            )));
        }
        write_triple(&mut buf, b"v ", p)?;
        flush(&mut buf, w, false)?;
    }

    if let Some(normals) = opts.normals {
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
        for (i, n) in normals.iter().enumerate() {
            if !n.iter().all(|c| c.is_finite()) {
                return Err(invalid_data(format!(
                    "the normal of vertex {i} is not finite ({}, {}, {})",
                    n[0], n[1], n[2]
                )));
            }
            write_triple(&mut buf, b"vn ", n)?;
            flush(&mut buf, w, false)?;
        }
    }

    let with_normals = opts.normals.is_some();
    for face in mesh.faces() {
        buf.push(b'f');
        for &v in face {
            let v = u64::from(v) + 1;
            buf.push(b' ');
            push_u64(&mut buf, v);
            if with_normals {
                buf.extend_from_slice(b"//");
                push_u64(&mut buf, v);
            }
        }
        buf.push(b'\n');
        flush(&mut buf, w, false)?;
    }

    if let Some(scheme) = opts.scheme {
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
    }
    for c in &mesh.tags.creases {
        check_sharpness(c.sharpness, || {
            format!("the crease on edge ({}, {})", c.v0, c.v1)
        })?;
        writeln!(buf, "t crease 2/1/0 {} {} {}", c.v0, c.v1, c.sharpness)?;
        flush(&mut buf, w, false)?;
    }
    for c in &mesh.tags.corners {
        check_sharpness(c.sharpness, || format!("the corner at vertex {}", c.vertex))?;
        writeln!(buf, "t corner 1/1/0 {} {}", c.vertex, c.sharpness)?;
        flush(&mut buf, w, false)?;
    }
    for chunk in mesh.tags.holes.chunks(HOLES_PER_LINE) {
        write!(buf, "t hole {}/0/0", chunk.len())?;
        for &f in chunk {
            buf.push(b' ');
            push_u64(&mut buf, u64::from(f));
        }
        buf.push(b'\n');
        flush(&mut buf, w, false)?;
    }
    write_knots(&mut buf, w, mesh)?;
    flush(&mut buf, w, true)
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

/// `prefix x y z\n` with shortest round-trip `f64`s.
fn write_triple(buf: &mut Vec<u8>, prefix: &[u8], p: &[f64; 3]) -> io::Result<()> {
    buf.extend_from_slice(prefix);
    writeln!(buf, "{} {} {}", p[0], p[1], p[2])
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
