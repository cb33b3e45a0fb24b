//! `subsurf blend`: join N bicubic B-spline patches C2 with a non-uniform Catmull-Clark
//! (NURSS) blend surface refined with skirt removal (seed 002 §3.1).

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::Args;
use subsurf::blend::blend;
use subsurf::blend::BlendError;
use subsurf::io::geometry::{read_geometry, SourcedGeometry};
use subsurf::io::obj::write_groups_obj;
use subsurf::io::obj::{write_obj, WriteOptions};
use subsurf::mesh::PolyMesh;
use subsurf::nurbs::{BSplineSurface, Geometry, Surface};

use crate::output::Output;

/// Examples shown by `subsurf blend --help`.
pub const BLEND_EXAMPLES: &str = "\
Input: N >= 2 bicubic B-spline patches (JSON or OBJ free-form, see `subsurf nurbs`), at least
4x4 control points, any knots, listed in order around the region to blend. Each patch is
blended along its first row (u = u_3); the end (last column) of each patch faces the start
(first column) of the next. Output: OBJ with one group per base patch (`patch_1`, ...) and the
blend surface (`blend`); --control-mesh writes the blend control mesh with its `t interval`
tags (its outer ring is the extension layer).

Examples:
  subsurf blend examples/patches/blend3.json -o blend3.obj
  subsurf blend examples/patches/blend5.json -o blend5.obj --levels 6 --control-mesh blend5-control.obj";

/// Arguments of `subsurf blend`.
#[derive(Debug, Args)]
pub struct BlendArgs {
    /// Input file: bicubic B-spline patches as JSON documents or OBJ free-form elements
    /// ('-' reads standard input).
    #[arg(value_name = "PATCHES")]
    pub input: PathBuf,
    /// Output OBJ file ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Skirt-removal refinement steps.
    #[arg(long, value_name = "L", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=8))]
    pub levels: u32,
    /// Segments per knot span of the tessellated base patches.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=256))]
    pub samples: u32,
    /// Also write the blend control mesh (OBJ with `t interval` tags) here.
    #[arg(long, value_name = "OUT2")]
    pub control_mesh: Option<PathBuf>,
}

/// The surfaces of `items` as polynomial bicubic candidates, or an error naming the item.
pub fn patches(items: &[SourcedGeometry]) -> Result<Vec<BSplineSurface<3>>> {
    items
        .iter()
        .map(|g| match &g.geometry {
            Geometry::Surface(Surface::BSpline(s)) => Ok(s.clone()),
            Geometry::Surface(Surface::Nurbs(_)) => bail!(
                "{}: a rational (NURBS) patch; blending takes non-rational B-spline patches",
                g.label()
            ),
            Geometry::Curve(_) => bail!("{}: a curve; blending takes patches", g.label()),
        })
        .collect()
}

/// A library error, prefixed with the file position and name of the input item it is about
/// (the library numbers items from 0, as the JSON `[i]` positions do).
pub fn explain(e: BlendError, items: &[SourcedGeometry]) -> anyhow::Error {
    match e.input_index().and_then(|i| items.get(i)) {
        Some(item) => anyhow::anyhow!("{}: {e}", item.label()),
        None => anyhow::anyhow!("{e}"),
    }
}

/// Runs `subsurf blend`.
pub fn run(args: &BlendArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let control_out = args.control_mesh.as_deref().map(Output::new);
    if let Some(c) = &control_out {
        c.check()?;
    }
    let items = read_geometry(&args.input)?;
    let patches = patches(&items)?;
    let b = blend(&patches, args.levels).map_err(|e| explain(e, &items))?;
    let surface = b.surface()?;
    let tessellated = patches
        .iter()
        .map(|s| Surface::BSpline(s.clone()).grid(args.samples as usize))
        .collect::<Result<Vec<PolyMesh>, _>>()?;
    let mut groups: Vec<(String, &PolyMesh)> = tessellated
        .iter()
        .enumerate()
        .map(|(k, m)| (format!("patch_{}", k + 1), m))
        .collect();
    groups.push(("blend".to_string(), &surface));
    let comment = format!(
        "subsurf blend: {} patches, {} skirt-removal levels",
        patches.len(),
        args.levels
    );
    out.write(|w| write_groups_obj(w, Some(&comment), &groups, &[]))?;
    if let Some(c) = control_out {
        let opts = WriteOptions {
            comment: Some("subsurf blend: control mesh (outer ring: extension layer)"),
            ..Default::default()
        };
        c.write(|mut w| write_obj(&mut w, &b.control.mesh, &opts))?;
    }
    Ok(())
}
