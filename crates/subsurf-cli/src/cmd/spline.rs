//! `subsurf spline`: the sub-basis spline surface ([Sub-basis splines]) of a quad mesh, tessellated and
//! written as OBJ, PLY, STL or glTF, optionally with alternating patch colours, one basis function
//! as a scalar, or a comparison with the Catmull-Clark limit surface.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use rayon::prelude::*;
use subsurf::io::{write_tessellation, Colours, TessellationFormat, TessellationWriteOptions};
use subsurf::limit::{tessellate, Tessellation};
use subsurf::spline::{
    compare_with_limit, face_colours, quad_control_mesh, scalar_colours, SubBasisSurface, PALETTE,
};

use crate::input::Input;
use crate::output::{formats, tessellation_format, Output};

/// Help text after the options of `subsurf spline`.
pub const SPLINE_EXAMPLES: &str = "\
The surface is a weighted sum of the control points with one non-negative basis function per
point (a rational bicubic patch per quad); on a regular quad mesh it is the uniform bicubic
B-spline (= the Catmull-Clark limit). A mesh with non-quad faces gets one Catmull-Clark step
first (said on stderr); face and vertex numbers then refer to the refined mesh, whose first
vertices are the input's. Faces with a corner on the boundary (or a non-manifold or
valence-2 corner) have no surface and are left out. Each face becomes N x N quads; shared
samples are evaluated once, so the output is watertight.

--colour-faces colours neighbouring patches differently (as in the paper's Fig. 7): OBJ gets
'v x y z r g b' vertex colours, each patch with its own copies of its border vertices; PLY
keeps shared vertices and gets 'red green blue' face properties. --basis V writes the
normalised basis function of control point V: OBJ as vertex colours (blue 0 to red max), PLY
as a 'basis' double vertex property plus colours. --report prints the distance to the
Catmull-Clark limit surface and the normal-angle jumps across edges.

Examples:
  subsurf spline model.obj -o model-spline.obj --rate 8
  subsurf spline model.obj -o patches.ply --colour-faces
  subsurf spline model.obj -o w12.ply --basis 12 --rate 16
  subsurf spline model.obj -o model-spline.obj --report";

/// Arguments of `subsurf spline`.
#[derive(Debug, Args)]
pub struct SplineArgs {
    /// Input OBJ file ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output file, .obj, .ply or .stl ('-' writes OBJ to standard output); written only
    /// when everything succeeded.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Segments per control-mesh edge: each face becomes N x N quads.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub rate: u32,
    /// Colour neighbouring patches differently (OBJ or PLY output).
    #[arg(long, visible_alias = "color-faces", conflicts_with = "basis")]
    pub colour_faces: bool,
    /// Export the basis function of control point V (0-based) as a scalar (OBJ or PLY).
    #[arg(long, value_name = "V")]
    pub basis: Option<u32>,
    /// Print the distance to the Catmull-Clark limit surface and the normal jumps across
    /// edges at irregular vertices.
    #[arg(long)]
    pub report: bool,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
    /// Print no notes.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Peak bytes per sub-basis piece of the surface (a piece is 40 bytes; measured with the
/// rest of the surface at poles of valence 1000 and 2000: 42–44).
const BYTES_PER_PIECE: u64 = 48;

/// Peak bytes per face of the surface besides its pieces and samples (its rational
/// patch, the topology, the input; measured on a closed 400 × 400 quad torus: 980).
const BYTES_PER_FACE: u64 = 1280;

/// Peak bytes per tessellation sample, writing included (measured between rates 512 and
/// 1024 on the cube: 193 for OBJ and PLY, with --basis or --colour-faces PLY; 215 for
/// --colour-faces OBJ between rates 128 and 256).
const BYTES_PER_SAMPLE: u64 = 256;

/// An upper bound of the peak memory of `subsurf spline` on the quad mesh `mesh` at `rate`:
/// every face keeps the sub-basis pieces of its four corners, `1 + 2 n` for a corner of
/// valence `n` (so a pole of valence `n` costs `n (2 n + 1)` pieces: quadratic), and the
/// tessellation has at most `(rate + 1)²` samples per face. Measured (release build, peak
/// RSS by `/usr/bin/time -v`), in RELIABILITY.md.
fn estimate_memory(mesh: &subsurf::mesh::PolyMesh, rate: u32) -> u64 {
    let mut faces_at = vec![0u64; mesh.num_vertices()];
    for f in mesh.faces() {
        for &v in f {
            faces_at[v as usize] += 1;
        }
    }
    let pieces = mesh
        .faces()
        .flat_map(|f| f.iter().map(|&v| 1 + 2 * faces_at[v as usize]))
        .fold(0u64, u64::saturating_add);
    let faces = mesh.num_faces() as u64;
    let samples = crate::memory::tessellation_vertices(mesh, rate);
    pieces
        .saturating_mul(BYTES_PER_PIECE)
        .saturating_add(faces.saturating_mul(BYTES_PER_FACE))
        .saturating_add(samples.saturating_mul(BYTES_PER_SAMPLE))
}

/// Runs `subsurf spline`.
pub fn run(args: &SplineArgs) -> Result<()> {
    let format = tessellation_format(&args.output, formats::SPLINE)?;
    if format == TessellationFormat::Stl && (args.colour_faces || args.basis.is_some()) {
        bail!(
            "--colour-faces and --basis need an .obj, .ply or .glb output (STL has no \
             colours); {} is STL",
            args.output.display()
        );
    }
    let out = Output::new(&args.output);
    if args.report && matches!(out, Output::Stdout) {
        bail!("--report prints to standard output: write the surface to a file, not '-'");
    }
    out.check()?;
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            crate::output::eprint_line(&format!("warning: {w}"));
        }
    }
    if !input.obj.mesh.tags.is_empty() && !args.quiet {
        crate::output::eprint_line(&format!(
            "note: {}: crease, corner and hole tags are ignored (the spline surface has no \
             sharp features)",
            input.name
        ));
    }
    let (control, subdivided) =
        quad_control_mesh(&input.obj.mesh).with_context(|| input.name.clone())?;
    crate::memory::check(
        &input.name,
        &format!("the spline surface at rate {}", args.rate),
        estimate_memory(&control, args.rate),
        args.max_memory,
        if args.rate > 1 {
            "use a lower --rate"
        } else {
            "the mesh is too large (a vertex of valence n costs n (2n + 1) sub-basis pieces)"
        },
    )?;
    let surface = SubBasisSurface::new(&control).with_context(|| input.name.clone())?;
    let (mesh, surface) = (control.as_ref(), &surface);
    if subdivided && !args.quiet {
        crate::output::eprint_line(&format!(
            "note: {}: the mesh has non-quad faces; applied one Catmull-Clark step first \
             ({} quads, {} control points)",
            input.name,
            mesh.num_faces(),
            mesh.num_vertices()
        ));
    }
    let missing = (0..mesh.num_faces())
        .filter(|&f| !surface.has_surface(f))
        .count();
    if missing > 0 && !args.quiet {
        crate::output::eprint_line(&format!(
            "note: {}: {missing} of {} faces have no surface (a corner on the boundary, \
             non-manifold or of valence 2)",
            input.name,
            mesh.num_faces()
        ));
    }
    if let Some(v) = args.basis {
        if v as usize >= mesh.num_vertices() {
            bail!(
                "{}: --basis {v}: there are only {} control points (0 to {})",
                input.name,
                mesh.num_vertices(),
                mesh.num_vertices() - 1
            );
        }
    }
    if !(0..mesh.num_faces()).any(|f| surface.has_surface(f)) {
        bail!(
            "{}: no face has a spline surface (every face has a corner on the boundary)",
            input.name
        );
    }
    // glTF draws triangles: let the tessellation split its quads (it picks the diagonals).
    let triangles = format == TessellationFormat::Glb;
    let t = tessellate(surface, mesh, args.rate, triangles).with_context(|| input.name.clone())?;
    let comment = format!(
        "subsurf spline --rate {}{}{} {}",
        args.rate,
        if args.colour_faces {
            " --colour-faces"
        } else {
            ""
        },
        args.basis
            .map_or(String::new(), |v| format!(" --basis {v}")),
        input.name
    );
    write_surface(&out, format, args, &t, surface, mesh, &comment)?;
    if args.report {
        print_report(&input.name, surface, mesh, args.rate)?;
    }
    Ok(())
}

/// Writes `t`, the tessellation of `surface`, to `out` in `format`: coloured by
/// face (`--colour-faces`), by one control point's basis function (`--basis`; in PLY also
/// its value, property `basis`), or plain.
fn write_surface(
    out: &Output,
    format: TessellationFormat,
    args: &SplineArgs,
    t: &Tessellation,
    surface: &SubBasisSurface,
    mesh: &subsurf::mesh::PolyMesh,
    comment: &str,
) -> Result<()> {
    let colours: Vec<[u8; 3]>;
    let values: Vec<f64>;
    let mut options = TessellationWriteOptions {
        comment,
        ..Default::default()
    };
    if args.colour_faces {
        let colour = face_colours(mesh)?;
        colours = (t.source.iter())
            .map(|&(f, _)| PALETTE[colour[f as usize] as usize % PALETTE.len()])
            .collect();
        options.colours = Some(Colours::PerFace(&colours));
    } else if let Some(v) = args.basis {
        values = t
            .points
            .par_iter()
            .map(|p| surface.weight_of(v, p.face, p.u, p.v))
            .collect::<Result<_, _>>()?;
        colours = scalar_colours(&values);
        options.colours = Some(Colours::PerVertex(&colours));
        if format == TessellationFormat::Ply {
            options.vertex_scalar = Some(("basis", &values));
        }
    }
    out.write(|mut w| write_tessellation(&mut w, format, t, &options))
}

/// Prints the comparison of `surface` with the Catmull-Clark limit surface of `mesh`.
fn print_report(
    name: &str,
    surface: &SubBasisSurface,
    mesh: &subsurf::mesh::PolyMesh,
    rate: u32,
) -> Result<()> {
    let c = compare_with_limit(surface, mesh, rate.clamp(2, 16))?;
    let report = format!(
        "{}: spline surface vs Catmull-Clark limit surface, {} faces, {} samples\n\
         distance at equal parameters: max {:.6e} ({:.3}% of the bounding-box diagonal \
         {:.6}) on face {}, rms {:.6e}\n\
         normal jumps across edges at irregular vertices ({} edges): max {:.4} deg, mean \
         of per-edge max {:.4} deg; at the irregular vertices themselves: max {:.2e} deg\n\
         normal jumps across edges between regular vertices ({} edges): max {:.2e} deg\n",
        name,
        c.faces,
        c.samples,
        c.max_distance,
        100.0 * c.max_distance / c.size.max(f64::MIN_POSITIVE),
        c.size,
        c.max_distance_face,
        c.rms_distance,
        c.irregular_edges,
        c.max_jump_irregular,
        c.mean_jump_irregular,
        c.max_jump_at_vertices,
        c.regular_edges,
        c.max_jump_regular
    );
    crate::output::print(&report)?;
    Ok(())
}
