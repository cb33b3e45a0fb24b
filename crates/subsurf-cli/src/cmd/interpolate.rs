//! `subsurf interpolate`: a control mesh whose non-uniform Catmull-Clark (NURSS) limit
//! surface passes through the given cubic B-spline / NURBS curves (symmetric zonal meshes,
//! seed 001), optionally refined or moved onto the limit surface, with the curves as OBJ
//! polylines for checking.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use subsurf::interpolate::{interpolate_geometry, InterpolateOptions, DEFAULT_WIDTH};
use subsurf::io::geometry::read_geometry;
use subsurf::io::obj::{write_obj, WriteOptions};
use subsurf::nurbs::Geometry;

use crate::output::Output;

/// Examples shown by `subsurf interpolate --help`.
pub const INTERPOLATE_EXAMPLES: &str = "\
Input: cubic curves (B-spline or NURBS, open or closed, any knots) as JSON or OBJ free-form
(see `subsurf nurbs`). Curves may cross at a shared control point (two curves per point, with
neighbours symmetric about it and equal knot intervals on the four edges around it), or one may
end on another (an unclamped end).
Output: OBJ quads with `t interval` / `t weight` tags (refine with `subsurf subdivide`, which
uses NURSS for tagged meshes), then the curves as polylines (`l`, group `curves`).

Examples:
  subsurf interpolate examples/curves/vase.json -o vase.obj
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
    /// the curve's size (the diagonal of its control points' bounding box).
    #[arg(long, value_name = "W", default_value_t = DEFAULT_WIDTH, allow_negative_numbers = true)]
    pub width: f64,
    /// Side direction X,Y,Z: side points are offset along it (projected perpendicular to the
    /// curve) instead of a rotation-minimising frame.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, allow_negative_numbers = true)]
    pub side: Option<[f64; 3]>,
    /// Refine L levels with NURSS before writing (0: the control mesh).
    #[arg(long, value_name = "L", value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: Option<u32>,
    /// Move the refined vertices onto the limit surface (with 4 levels unless --levels).
    #[arg(long)]
    pub tessellate: bool,
    /// Segments per knot span of the curve polylines; 0 leaves the curves out.
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(0..=1000))]
    pub curve_samples: u32,
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
    let opts = InterpolateOptions {
        width: args.width,
        side: args.side,
    };
    let zones = interpolate_geometry(&items, &opts)?;
    let levels = match (args.levels, args.tessellate) {
        (Some(l), _) => l,
        (None, true) => 4,
        (None, false) => 0,
    };
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
    let comment = format!(
        "subsurf interpolate: {} curve zone(s), width {}, {}{}",
        zones.zones.len(),
        args.width,
        if args.tessellate {
            format!("limit surface after {levels} NURSS levels")
        } else if levels > 0 {
            format!("{levels} NURSS levels")
        } else {
            "control mesh with knot intervals".into()
        },
        if curves.is_empty() {
            String::new()
        } else {
            "; curves as polylines in group 'curves'".into()
        }
    );
    let wopts = WriteOptions {
        normals: None,
        scheme: None,
        comment: Some(&comment),
    };
    let base = mesh.num_vertices();
    out.write(|mut w| {
        write_obj(&mut w, &mesh, &wopts)?;
        if curves.is_empty() {
            return Ok(());
        }
        let mut buf = String::from("g curves\n");
        let mut next = base + 1;
        let mut lines = String::new();
        for poly in &curves {
            lines.push('l');
            for p in poly {
                buf.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
                lines.push_str(&format!(" {next}"));
                next += 1;
            }
            lines.push('\n');
        }
        buf.push_str(&lines);
        w.write_all(buf.as_bytes())
    })
}
