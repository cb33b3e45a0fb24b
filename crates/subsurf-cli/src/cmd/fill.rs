//! `subsurf fill`: fill an N-sided hole bounded by cubic B-spline curves or patches with a
//! corner-interpolating non-uniform Catmull-Clark (NURSS) surface ([Jiang et al.], Algorithm 1).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use subsurf::blend::fill_g1;
use subsurf::blend::{fill, surface_boundary, FillOptions};
use subsurf::io::read_geometry;
use subsurf::io::write_groups_obj;
use subsurf::io::{write_obj, WriteOptions};
use subsurf::mesh::PolyMesh;
use subsurf::nurbs::{sample_parameters, Curve, Geometry, Surface};

use super::blend::{check_memory, explain, input_name, sample_points};
use crate::output::Output;

/// Examples shown by `subsurf fill --help`.
pub const FILL_EXAMPLES: &str = "\
Input: 3 to 8 cubic B-spline or NURBS curves, or bicubic patches (their first-row boundary
u = u_3 is used), as JSON or OBJ free-form (see `subsurf nurbs`), meeting end to end around
the hole (in any direction). The fill interpolates every boundary curve and the corners
(NURBS input is filled in homogeneous coordinates and interpolated exactly; --g1 takes
polynomial patches, or NURBS patches with one weight each). --bulge B moves
the free inner control points along the boundary's normal by B times the hole's radius
(B > 0 convex, B < 0 concave). --g1 (patches only) makes the fill meet every patch with a
continuous normal (the paper's Algorithm 2; neighbouring patches must share the tangent plane
at their common corner). Output: OBJ with the base patches (`patch_1`, ...) when
patches were given, the boundary curves as polylines (`curve_1`, ...) and the fill (`fill`).

Examples:
  subsurf fill examples/patches/hole3.json -o hole3.obj
  subsurf fill examples/patches/hole5.json -o hole5.obj --bulge 0.4 --levels 5
  subsurf fill examples/patches/hole3.json -o hole3-g1.obj --g1";

/// Arguments of `subsurf fill`.
#[derive(Debug, Args)]
pub struct FillArgs {
    /// Input file: cubic curves or bicubic patches as JSON documents or OBJ free-form
    /// elements ('-' reads standard input).
    #[arg(value_name = "PATCHES")]
    pub input: PathBuf,
    /// Output OBJ file ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Skirt-removal refinement steps.
    #[arg(long, value_name = "L", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: u32,
    /// Convex (> 0) or concave (< 0) fill: moves the free inner points along the normal.
    #[arg(
        long,
        value_name = "B",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = parse_bulge
    )]
    pub bulge: f64,
    /// Meet the base patches G1 (continuous normal; needs patches, not curves).
    #[arg(long)]
    pub g1: bool,
    /// Segments per knot span of the tessellated patches and curve polylines.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub samples: u32,
    /// Also write the fill control mesh (OBJ with `t interval` tags) here.
    #[arg(long, value_name = "OUT2")]
    pub control_mesh: Option<PathBuf>,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Parses `--bulge B`: a finite number.
fn parse_bulge(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(b) if b.is_finite() => Ok(b),
        _ => Err(format!("'{s}' is not a finite number")),
    }
}

/// Runs `subsurf fill`.
pub fn run(args: &FillArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let control_out = args.control_mesh.as_deref().map(Output::new);
    if let Some(c) = &control_out {
        c.check()?;
    }
    let name = input_name(&args.input);
    let items = read_geometry(&args.input)?;
    let mut curves: Vec<Curve> = Vec::with_capacity(items.len());
    let mut surfaces: Vec<Surface> = Vec::new();
    for (k, g) in items.iter().enumerate() {
        match &g.geometry {
            Geometry::Curve(_) if args.g1 => bail!(
                "{}: a curve; --g1 needs the patches around the hole (their normals)",
                g.label()
            ),
            Geometry::Curve(c) => curves.push(c.clone()),
            Geometry::Surface(s) => {
                curves.push(surface_boundary(s, k).map_err(|e| explain(e, &items, &name))?);
                surfaces.push(s.clone());
            }
        }
    }
    let opts = FillOptions {
        bulge: args.bulge,
        ..Default::default()
    };
    let fail = |e| explain(e, &items, &name);
    // The control mesh first (no refinement): its size bounds the job's memory.
    let control = if args.g1 {
        fill_g1(&surfaces, 0, &opts).map_err(fail)?.control
    } else {
        fill(&curves, 0, &opts).map_err(fail)?.control
    };
    let samples = sample_points(&surfaces, args.samples).saturating_add(
        curves
            .iter()
            .map(|c| sample_parameters(c.knots(), args.samples as usize).len() as u64)
            .sum(),
    );
    check_memory(
        &name,
        "filling",
        &control,
        args.levels,
        samples,
        args.max_memory,
    )?;
    let (surface, boundary, control) = if args.g1 {
        let f = fill_g1(&surfaces, args.levels, &opts).map_err(fail)?;
        let curves = f.curves.iter().cloned().map(Curve::BSpline).collect();
        (f.surface().map_err(fail)?, curves, f.control)
    } else {
        let f = fill(&curves, args.levels, &opts).map_err(fail)?;
        (f.surface().map_err(fail)?, f.curves, f.control)
    };
    let tessellated = surfaces
        .iter()
        .map(|s| s.grid(args.samples as usize))
        .collect::<Result<Vec<PolyMesh>, _>>()
        .with_context(|| name.clone())?;
    let mut groups: Vec<(String, &PolyMesh)> = tessellated
        .iter()
        .enumerate()
        .map(|(k, m)| (format!("patch_{}", k + 1), m))
        .collect();
    groups.push(("fill".to_string(), &surface));
    let polylines = boundary
        .iter()
        .enumerate()
        .map(|(k, c)| {
            c.polyline(args.samples as usize)
                .map(|p| (format!("curve_{}", k + 1), p))
        })
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| name.clone())?;
    let comment = format!(
        "subsurf fill: {}-sided hole{}, {} skirt-removal levels, bulge {}",
        curves.len(),
        if args.g1 { " (G1)" } else { "" },
        args.levels,
        args.bulge
    );
    out.write(|w| write_groups_obj(w, Some(&comment), &groups, &polylines))?;
    if let Some(c) = control_out {
        let wopts = WriteOptions {
            comment: Some("subsurf fill: control mesh (outer ring: extension layer)"),
            ..Default::default()
        };
        c.write(|mut w| write_obj(&mut w, &control, &wopts))?;
    }
    Ok(())
}
