//! OBJ output of several meshes as named groups (`g`) and curves as polylines (`l`) in one
//! file, with one shared vertex list (blends and fills with their base patches, sampled
//! curves and surfaces).

use std::io::{self, Write};

use crate::blend::MethodOutput;
use crate::io::push_decimal;
use crate::mesh::PolyMesh;

/// `v x y z\n` with [`push_decimal`].
fn write_vertex(w: &mut dyn Write, p: &[f64; 3]) -> io::Result<()> {
    let mut line = Vec::with_capacity(80);
    line.extend_from_slice(b"v");
    for &x in p {
        line.push(b' ');
        push_decimal(&mut line, x);
    }
    line.push(b'\n');
    w.write_all(&line)
}

/// Writes `groups` (each `g name` followed by its faces) and `polylines` (each `g name`
/// followed by one `l` statement) as one OBJ document, after an optional `# comment` line.
/// Coordinates are written as [`write_obj`](super::write_obj) writes them
/// ([`push_decimal`]).
///
/// # Errors
/// Those of `w`.
pub fn write_groups_obj(
    w: &mut dyn Write,
    comment: Option<&str>,
    groups: &[(String, &PolyMesh)],
    polylines: &[(String, Vec<[f64; 3]>)],
) -> io::Result<()> {
    if let Some(c) = comment {
        for line in c.lines() {
            writeln!(w, "# {line}")?;
        }
    }
    let mut base = 1usize;
    for (name, mesh) in groups {
        writeln!(w, "g {name}")?;
        for p in mesh.positions() {
            write_vertex(w, p)?;
        }
        for f in mesh.faces() {
            write!(w, "f")?;
            for &v in f {
                write!(w, " {}", base + v as usize)?;
            }
            writeln!(w)?;
        }
        base += mesh.num_vertices();
    }
    for (name, pts) in polylines {
        writeln!(w, "g {name}")?;
        for p in pts {
            write_vertex(w, p)?;
        }
        write!(w, "l")?;
        for i in 0..pts.len() {
            write!(w, " {}", base + i)?;
        }
        writeln!(w)?;
        base += pts.len();
    }
    Ok(())
}

/// Writes a blend or fill ([`MethodOutput`]) as `subsurf blend` and `subsurf fill` do: its
/// comment, the base patches (`patch_1`, …), the surface (`blend` or `fill`) and the
/// boundary polylines (`curve_1`, …), by [`write_groups_obj`].
///
/// # Errors
/// Those of `w`.
pub fn write_method_obj(w: &mut dyn Write, output: &MethodOutput) -> io::Result<()> {
    write_groups_obj(
        w,
        Some(&output.comment),
        &output.groups(),
        &output.polylines(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_share_one_vertex_numbering() {
        let q = PolyMesh::from_faces(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            &[[0u32, 1, 2]],
        )
        .unwrap();
        let mut out = Vec::new();
        let groups = [("a".to_string(), &q), ("b".to_string(), &q)];
        let lines = [("c".to_string(), vec![[0.0, 0.0, 1.0], [0.5, 0.0, 1.0]])];
        write_groups_obj(&mut out, Some("test"), &groups, &lines).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("# test\ng a\n"));
        assert!(text.contains("g b\n") && text.contains("f 4 5 6\n") && text.contains("l 7 8\n"));
    }
}
