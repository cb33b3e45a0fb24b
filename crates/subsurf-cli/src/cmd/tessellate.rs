//! `subsurf tessellate`: sample the exact limit surface on a watertight grid and write it
//! as OBJ (with normals), binary PLY (with normals), binary STL or binary glTF (`.glb`,
//! triangles with normals, optionally with the control mesh's edges as lines).

use anyhow::{bail, Context, Result};
use subsurf::io::Up;
use subsurf::io::{write_tessellation, TessellationFormat, TessellationWriteOptions};
use subsurf::limit::{
    tessellate, BilinearSurface, FaceVaryingSurface, LimitSurface, LoopSurface, Surface,
    Tessellation,
};
use subsurf::mesh::{Options, PolyMesh, TriangleSubdivision};
use subsurf::{Mixed, Scheme};

use crate::input::Input;
use crate::output::{formats, tessellation_format, Output};
use crate::{SchemeKind, TessellateArgs};

/// Peak bytes per output vertex, writing included (measured: 118 for OBJ, 99 for PLY, at
/// 6 million vertices).
const BYTES_PER_VERTEX: u64 = 128;

/// Bytes per output vertex for texture coordinates: about four corners per vertex (an
/// index and an evaluation request each), a value (16 bytes) and, in PLY and glTF, a
/// vertex's copy.
const UV_BYTES_PER_VERTEX: u64 = 96;

/// `subsurf tessellate` of the non-uniform (NURSS) limit surface, through refinement.
fn run_nurss(
    args: &TessellateArgs,
    input: &Input,
    options: &Options,
    format: TessellationFormat,
    out: &Output,
) -> Result<()> {
    let mesh = &input.obj.mesh;
    let rate = args.rate.max(1).next_power_of_two();
    // NURSS keeps whole levels of homogeneous points and their topology: about three times
    // what the Catmull-Clark sampling needs per output vertex; each face-varying channel
    // refined with them (its value mesh, a level of its own) about two times more.
    let verts = crate::memory::tessellation_vertices(mesh, rate);
    let copies = 3 + 2 * mesh.face_varying.len() as u64;
    crate::memory::check(
        &input.name,
        &format!("sampling the NURSS surface at rate {rate}"),
        verts.saturating_mul(copies * BYTES_PER_VERTEX),
        args.max_memory,
        "use a lower --rate",
    )?;
    let triangles = args.triangles || format == TessellationFormat::Glb;
    // Texture coordinates are refined with the surface and written at their limit.
    let t = subsurf::nonuniform::tessellate(mesh, options, args.rate, triangles)
        .with_context(|| input.name.clone())?;
    stl_note(format, &t, input, args.quiet);
    if t.rate != args.rate && !args.quiet {
        crate::output::eprint_line(&format!(
            "note: {}: rate {} rounded up to {}: the NURSS surface is sampled through \
             refinement (2^L samples per edge)",
            input.name, args.rate, t.rate
        ));
    }
    let mut comment = command_line(args, options, &input.name);
    comment.insert_str("subsurf tessellate".len(), " --scheme nurss");
    let control = args.control_mesh.then_some(mesh);
    check_single_precision(&t, format, input)?;
    write(out, format, &t, &comment, control, up(args))
}

/// Runs `subsurf tessellate`.
pub fn run(args: &TessellateArgs) -> Result<()> {
    super::adjustable::check_surface_flags(args.scheme_kind, &args.adjust);
    let format = output_format(args)?;
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            crate::output::eprint_line(&format!("warning: {w}"));
        }
    }
    let mut options = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    if let Some(mode) = args.fvar {
        options.face_varying = mode;
    }
    let mesh = &input.obj.mesh;
    let kind = super::adjustable::surface_kind(args.scheme_kind, &args.adjust, &input, args.quiet);
    if kind == SchemeKind::Nurss {
        return run_nurss(args, &input, &options, format, &out);
    }
    // With --c: the mixed surface, the limit of the c-refined mesh at the rate per input edge.
    let mixed = super::adjustable::for_surface(&args.adjust);
    let refined = match mixed {
        Some(m) => Some(super::adjustable::refined_mesh(&input, options, m)?),
        None => None,
    };
    let (surface_mesh, rate) = match (&refined, mixed) {
        (Some(r), Some(m)) => (r, super::adjustable::refined_rate(args.rate, m.steps)),
        _ => (mesh, args.rate),
    };
    // Memory: the surface, then the samples (positions, normals, numbering) and the writer;
    // with texture coordinates their surface (a limit surface of the channel's value mesh,
    // estimated as the mesh's own) and a value and index per corner. Beyond the library's
    // cap on the output, `tessellate` refuses with the exact counts.
    let verts = crate::memory::tessellation_vertices(surface_mesh, rate);
    let uv_bytes = match uv_channel(surface_mesh) {
        Some(_) => LimitSurface::estimate_build_memory(surface_mesh)
            .saturating_add(verts.saturating_mul(UV_BYTES_PER_VERTEX)),
        None => 0,
    };
    let guard = crate::memory::SurfaceGuard {
        name: &input.name,
        what: format!("tessellating at rate {rate}"),
        max: args.max_memory,
        hint: "use a lower --rate",
        quads_only: false,
    };
    // Only the build is guarded beyond the library's cap: the tessellation is refused
    // before any evaluation.
    let (divisions, reserved) = if verts <= subsurf::limit::MAX_TESSELLATION_VERTICES {
        let held = verts.saturating_mul(BYTES_PER_VERTEX);
        (rate, held.saturating_add(uv_bytes))
    } else {
        (1, 0)
    };
    let m = surface_mesh;
    let (surface, scheme): (Box<dyn Surface>, _) = match kind {
        SchemeKind::Loop => {
            let s = guard.local_surface(LoopSurface::estimate_memory(m), reserved, || {
                LoopSurface::new(m, options)
            })?;
            (Box::new(s), Scheme::Loop)
        }
        SchemeKind::Bilinear => {
            let s =
                guard.local_surface(LimitSurface::estimate_build_memory(m), reserved, || {
                    BilinearSurface::new(m)
                })?;
            (Box::new(s), Scheme::Bilinear)
        }
        _ => {
            let s = guard.limit_surface(m, options, divisions, reserved)?;
            (Box::new(s), Scheme::CatmullClark)
        }
    };
    // glTF draws triangles: let the tessellation split its quads (it picks the diagonals).
    let triangles = args.triangles || format == TessellationFormat::Glb;
    let mut t =
        tessellate(&*surface, surface_mesh, rate, triangles).with_context(|| input.name.clone())?;
    drop(surface);
    add_uvs(&mut t, surface_mesh, scheme, &options, &input)?;
    // Not written: free them before the writer's buffers (BYTES_PER_VERTEX).
    t.points = Vec::new();
    stl_note(format, &t, &input, args.quiet);
    if t.rate != rate && !args.quiet {
        crate::output::eprint_line(&format!(
            "note: {}: rate {} rounded up to {}, as the mesh has non-quad faces \
             (each of their sub-faces gets {} × {} quads)",
            input.name,
            args.rate,
            t.rate,
            t.rate / 2,
            t.rate / 2
        ));
    }
    let comment = scheme_comment(args, &options, &input.name, mixed, scheme);
    let control = args.control_mesh.then_some(mesh);
    check_single_precision(&t, format, &input)?;
    write(&out, format, &t, &comment, control, up(args))
}

/// The output's format, checked against the flags that only some formats take.
fn output_format(args: &TessellateArgs) -> Result<TessellationFormat> {
    let format = tessellation_format(&args.output, formats::TESSELLATE)?;
    if args.control_mesh && format != TessellationFormat::Glb {
        bail!(
            "--control-mesh needs a .glb output ({} is not one)",
            args.output.display()
        );
    }
    if args.up.is_some() && format != TessellationFormat::Glb {
        bail!(
            "--up applies to a .glb output only ({} is not one; OBJ, PLY and STL keep the \
             input's axes)",
            args.output.display()
        );
    }
    Ok(format)
}

/// The output's comment: the command line with the surface's scheme flags (`--c` and
/// `--adjust-steps` of a mixed surface, `--scheme` of Loop and bilinear).
fn scheme_comment(
    args: &TessellateArgs,
    options: &Options,
    name: &str,
    mixed: Option<Mixed>,
    scheme: Scheme,
) -> String {
    let mut comment = command_line(args, options, name);
    if let Some(m) = mixed {
        let flags = format!(" --c {} --adjust-steps {}", m.scheme.c(), m.steps);
        comment.insert_str("subsurf tessellate".len(), &flags);
    }
    if matches!(scheme, Scheme::Loop | Scheme::Bilinear) {
        let flag = format!(" --scheme {}", scheme.name());
        comment.insert_str("subsurf tessellate".len(), &flag);
    }
    comment
}

/// A note (unless `quiet`) that an STL output has no texture coordinates when `t` has some.
fn stl_note(format: TessellationFormat, t: &Tessellation, input: &Input, quiet: bool) {
    let uv = t.face_varying.iter().any(|c| c.name() == "uv");
    if format == TessellationFormat::Stl && uv && !quiet {
        crate::output::eprint_line(&format!(
            "note: {}: STL stores no texture coordinates: they are not written (write .obj, \
             .ply or .glb to keep them)",
            input.name
        ));
    }
}

/// The index of `mesh`'s texture coordinates (the face-varying channel named `"uv"`).
fn uv_channel(mesh: &PolyMesh) -> Option<usize> {
    mesh.face_varying.iter().position(|c| c.name() == "uv")
}

/// Adds the limit of `mesh`'s texture coordinates (if any) under `scheme` at the corners of
/// `t`, sampled from `mesh` with `options` (whose face-varying mode applies).
fn add_uvs(
    t: &mut Tessellation,
    mesh: &PolyMesh,
    scheme: Scheme,
    options: &Options,
    input: &Input,
) -> Result<()> {
    let Some(c) = uv_channel(mesh) else {
        return Ok(());
    };
    let context = || format!("{}: texture coordinates", input.name);
    let surface =
        FaceVaryingSurface::for_scheme(mesh, scheme, *options, c).with_context(context)?;
    let uv = t
        .evaluate_face_varying(mesh, &surface, "uv")
        .with_context(context)?;
    t.face_varying.push(uv);
    Ok(())
}

/// The input's up axis (`--up`, Z by default), for a .glb output.
fn up(args: &TessellateArgs) -> Up {
    match args.up.as_deref() {
        Some("y") => Up::Y,
        _ => Up::Z,
    }
}

/// Refuses, naming the input, a tessellation that `format` cannot store: STL and glTF keep
/// single-precision coordinates, and a limit surface of coordinates beyond their range
/// (about 3.4e38; the input may have coordinates up to 1e75) would otherwise fail as the
/// output is written, as if the output were at fault. The message names the first face
/// (1-based, with its line) whose surface reaches beyond.
fn check_single_precision(
    t: &Tessellation,
    format: TessellationFormat,
    input: &Input,
) -> Result<()> {
    let what = match format {
        TessellationFormat::Stl => "STL",
        TessellationFormat::Glb => "glTF",
        _ => return Ok(()),
    };
    let beyond = |x: f64| !(x as f32).is_finite();
    let Some(v) = t
        .positions
        .iter()
        .position(|p| p.iter().any(|&x| beyond(x)))
    else {
        return Ok(());
    };
    let value = (t.positions[v].iter().copied())
        .find(|&x| beyond(x))
        .unwrap_or_default();
    let face = (0..t.num_faces()).find(|&f| t.face(f).contains(&(v as u32)));
    let base = face.and_then(|f| t.source.get(f)).map(|&(b, _)| b as usize);
    let at = match base {
        Some(b) => match input.obj.face_line(b) {
            Some(line) => format!("{}:{line}: face {}: ", input.name, b + 1),
            None => format!("{}: face {}: ", input.name, b + 1),
        },
        None => format!("{}: ", input.name),
    };
    bail!(
        "{at}the limit surface reaches {value:e}, beyond the single precision (about \
         ±3.4e38) that {what} stores; write .obj or .ply, which keep double precision"
    )
}

/// Writes `t` to `out` in `format` (for glTF: with `control`'s edges as lines, turned
/// from `up` to glTF's +Y up).
fn write(
    out: &Output,
    format: TessellationFormat,
    t: &Tessellation,
    comment: &str,
    control: Option<&PolyMesh>,
    up: Up,
) -> Result<()> {
    let options = TessellationWriteOptions {
        comment,
        control,
        up,
        ..Default::default()
    };
    out.write(|mut w| write_tessellation(&mut w, format, t, &options))
}

/// The command line that reproduces the output, for its header.
fn command_line(args: &TessellateArgs, s: &Options, input: &str) -> String {
    let mut line = format!(
        "subsurf tessellate --rate {} --boundary {} --crease-method {}",
        args.rate, s.boundary, s.crease_method
    );
    if s.triangles == TriangleSubdivision::Smooth {
        line.push_str(" --smooth-triangles");
    }
    if args.triangles {
        line.push_str(" --triangles");
    }
    if args.control_mesh {
        line.push_str(" --control-mesh");
    }
    if let Some(up) = &args.up {
        line.push_str(" --up ");
        line.push_str(up);
    }
    line.push(' ');
    line.push_str(input);
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_from_extensions() {
        let f = |p: &str| tessellation_format(std::path::Path::new(p), formats::TESSELLATE);
        assert_eq!(f("a.obj").unwrap(), TessellationFormat::Obj);
        assert_eq!(f("dir/a.PLY").unwrap(), TessellationFormat::Ply);
        assert_eq!(f("a.b.Stl").unwrap(), TessellationFormat::Stl);
        assert_eq!(f("a.GLB").unwrap(), TessellationFormat::Glb);
        assert_eq!(f("-").unwrap(), TessellationFormat::Obj);
        let e = f("a.xyz").unwrap_err().to_string();
        assert!(
            e.contains("'.xyz'") && e.contains(".obj, .ply, .stl or .glb"),
            "{e}"
        );
        assert!(f("noext").is_err());
    }
}
