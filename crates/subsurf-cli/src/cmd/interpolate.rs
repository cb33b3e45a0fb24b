//! `subsurf interpolate`: a control mesh whose non-uniform Catmull-Clark (NURSS) limit
//! surface passes through the given cubic B-spline / NURBS curves (symmetric zonal meshes,
//! [JOS 2003]), optionally refined or moved onto the limit surface, with the curves as OBJ
//! polylines for checking.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use subsurf::curves::{
    embed_geometry, interpolate_geometry, HostOptions, InterpolateOptions, Interpolation,
    DEFAULT_HOST_WIDTH, DEFAULT_WIDTH,
};
use subsurf::io::read_geometry;
use subsurf::io::{read_obj, write_obj, WriteOptions};
use subsurf::nurbs::Geometry;
use subsurf::nurbs::SourcedGeometry;

use crate::output::Output;

/// Examples shown by `subsurf interpolate --help`.
pub const INTERPOLATE_EXAMPLES: &str = "\
Input: cubic curves (B-spline or NURBS, open or closed, any knots) as JSON or OBJ free-form
(see `subsurf nurbs`). Up to four curves may share a control point: two lines through it, at
least 30 degrees apart, each holding one curve passing through (neighbours symmetric about the
point, equal knot intervals on the edges around it) or one or two curves ending there
(unclamped ends; two from opposite sides must continue each other). Two curves ending at one
point from nearly opposite directions are joined into one zone.
Output: OBJ quads with `t interval` / `t weight` tags (refine with `subsurf subdivide`, which
uses NURSS for tagged meshes), then the curves as polylines (`l`, group `curves`).

With --host HOST.obj the zones are inserted into a quad mesh whose edges contain the control
polygons (every control point a host vertex, open curves ending at interior vertices of valence
>= 4); --width is then the rows' distance from the polygon as a fraction of the host's edges.

Examples:
  subsurf interpolate examples/curves/vase.json -o vase.obj
  subsurf interpolate crates/subsurf-cli/examples/host-curve.json --host crates/subsurf-cli/examples/host-grid.obj -o embedded.obj
  subsurf interpolate examples/curves/vase.json -o vase-limit.obj --levels 4 --tessellate
  subsurf interpolate examples/curves/dolphin.json -o dolphin.obj --width 0.05 --side 0,0,1";

/// Arguments of `subsurf interpolate`.
#[derive(Debug, Args)]
pub struct InterpolateArgs {
    /// Input file: cubic curves as JSON documents or OBJ free-form elements ('-' reads
    /// standard input).
    #[arg(value_name = "CURVES")]
    pub input: PathBuf,
    /// Output OBJ file ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Zone width: distance of the side points from the curve's control polygon, relative to
    /// the curve's size (the diagonal of its control points' bounding box) [default: 0.05];
    /// with --host, as a fraction in (0, 1) of the shortest host edge leaving each control
    /// point [default: 1/3].
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub width: Option<f64>,
    /// Side direction X,Y,Z: side points are offset along it (projected perpendicular to the
    /// curve) instead of a rotation-minimising frame.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, allow_negative_numbers = true, conflicts_with = "host")]
    pub side: Option<[f64; 3]>,
    /// Host quad mesh (OBJ) whose edges contain the control polygons: the zones are inserted
    /// into it along the polygons (knot intervals and, at control points of valence > 4,
    /// auxiliary side intervals set as [JOS 2003]'s Fig. 11 requires).
    #[arg(long, value_name = "HOST.obj")]
    pub host: Option<PathBuf>,
    /// Refine L levels with NURSS before writing (0: the control mesh).
    #[arg(long, value_name = "L", value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: Option<u32>,
    /// Move the refined vertices onto the limit surface (with 4 levels unless --levels).
    #[arg(long)]
    pub tessellate: bool,
    /// Segments per knot span of the curve polylines; 0 leaves the curves out.
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub curve_samples: u32,
    /// Refuse to refine when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// `X,Y,Z` as three finite numbers.
fn parse_vector(s: &str) -> std::result::Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || format!("'{s}' is not a vector (expected X,Y,Z, e.g. 0,0,1)");
    if parts.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p.parse::<f64>().map_err(|_| bad())?;
        if !v[k].is_finite() {
            return Err(bad());
        }
    }
    Ok(v)
}

/// Runs `subsurf interpolate`.
pub fn run(args: &InterpolateArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let items = read_geometry(&args.input)?;
    let (zones, width) = build_zones(args, &items)?;
    let levels = match (args.levels, args.tessellate) {
        (Some(l), _) => l,
        (None, true) => 4,
        (None, false) => 0,
    };
    check_memory(args, &zones, levels)?;
    let mesh = if levels == 0 && !args.tessellate {
        zones.mesh.clone()
    } else {
        zones
            .refined_mesh(levels, args.tessellate)
            .context("cannot refine the zones")?
    };
    let mut curves = Vec::new();
    if args.curve_samples > 0 {
        for g in &items {
            if let Geometry::Curve(c) = &g.geometry {
                curves.push(c.polyline(args.curve_samples as usize)?);
            }
        }
    }
    let comment = header_comment(args, zones.zones.len(), width, levels, !curves.is_empty());
    let wopts = WriteOptions {
        normals: None,
        scheme: None,
        comment: Some(&comment),
    };
    out.write(|mut w| {
        write_obj(&mut w, &mesh, &wopts)?;
        if curves.is_empty() {
            return Ok(());
        }
        w.write_all(&polylines(&curves, mesh.num_vertices()))
    })
}

/// The curve zones of `items` and their width: embedded in the host mesh (`--host`), or
/// built around the curves alone.
fn build_zones(args: &InterpolateArgs, items: &[SourcedGeometry]) -> Result<(Interpolation, f64)> {
    Ok(match &args.host {
        Some(path) => {
            let host = read_obj(path)?.mesh;
            let width = args.width.unwrap_or(DEFAULT_HOST_WIDTH);
            let zones = embed_geometry(&host, items, &HostOptions { width })
                .with_context(|| format!("cannot embed the curves in {}", path.display()))?;
            (zones, width)
        }
        None => {
            let width = args.width.unwrap_or(DEFAULT_WIDTH);
            let opts = InterpolateOptions {
                width,
                side: args.side,
            };
            (interpolate_geometry(items, &opts)?, width)
        }
    })
}

/// Checks the memory of refining `zones` to `levels` (and to the limit with
/// `--tessellate`) against `--max-memory`. NURSS keeps every level complete and refines
/// homogeneous points, and the limit refines the last level's topology once more: three
/// times the Catmull-Clark estimate of the levels refined (one more for the limit), plus
/// the process itself (the measured peaks it covers are in BENCHMARKS.md, "Allocator
/// settings, kept buffers and memory estimates").
fn check_memory(args: &InterpolateArgs, zones: &Interpolation, levels: u32) -> Result<()> {
    let name = if args.input.as_os_str() == "-" {
        "<stdin>".to_string()
    } else {
        args.input.display().to_string()
    };
    let refined = subsurf::SubdivideOptions {
        levels: levels + u32::from(args.tessellate),
        ..Default::default()
    };
    let estimate = subsurf::estimate_memory(&zones.mesh, &refined)
        .saturating_mul(3)
        .saturating_add(16 << 20);
    crate::memory::check(
        &name,
        &format!(
            "refining the zones to level {levels}{}",
            if args.tessellate {
                " and moving them to the limit"
            } else {
                ""
            }
        ),
        estimate,
        args.max_memory,
        "use a lower --levels",
    )
}

/// The output's header comment: the zones, the host, the width, what the mesh is, and
/// where the curves are.
fn header_comment(
    args: &InterpolateArgs,
    zones: usize,
    width: f64,
    levels: u32,
    curves: bool,
) -> String {
    format!(
        "subsurf interpolate: {} curve zone(s){}, width {}, {}{}",
        zones,
        match &args.host {
            Some(h) => format!(" in host {}", h.display()),
            None => String::new(),
        },
        width,
        if args.tessellate {
            format!("limit surface after {levels} NURSS levels")
        } else if levels > 0 {
            format!("{levels} NURSS levels")
        } else {
            "control mesh with knot intervals".into()
        },
        if curves {
            "; curves as polylines in group 'curves'"
        } else {
            ""
        }
    )
}

/// The group `curves`: the vertices of the polylines `curves` (numbered after the mesh's
/// `base` vertices), then one `l` line per polyline.
fn polylines(curves: &[Vec<[f64; 3]>], base: usize) -> Vec<u8> {
    let mut buf = b"g curves\n".to_vec();
    let mut next = base + 1;
    let mut lines = String::new();
    for poly in curves {
        lines.push('l');
        for p in poly {
            buf.push(b'v');
            for &x in p {
                buf.push(b' ');
                subsurf::io::push_decimal(&mut buf, x);
            }
            buf.push(b'\n');
            lines.push_str(&format!(" {next}"));
            next += 1;
        }
        lines.push('\n');
    }
    buf.extend_from_slice(lines.as_bytes());
    buf
}
