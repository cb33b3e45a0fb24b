//! `subsurf blend`: join N bicubic B-spline or NURBS patches C2 with a non-uniform
//! Catmull-Clark (NURSS) blend surface refined with skirt removal ([Jiang et al.] §3.1).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use subsurf::blend::BlendError;
use subsurf::blend::{blend, blend_control_mesh};
use subsurf::io::read_geometry;
use subsurf::io::write_groups_obj;
use subsurf::io::{write_obj, WriteOptions};
use subsurf::mesh::PolyMesh;
use subsurf::nurbs::SourcedGeometry;
use subsurf::nurbs::{Geometry, Surface};

use crate::output::Output;

/// Examples shown by `subsurf blend --help`.
pub const BLEND_EXAMPLES: &str = "\
Input: N >= 2 bicubic B-spline or NURBS patches (JSON or OBJ free-form, see `subsurf nurbs`),
at least 4x4 control points, any knots, listed in order around the region to blend (NURBS
patches are blended in homogeneous coordinates: the blend joins them C2 too). Each patch is
blended along its first row (u = u_3); the end (last column) of each patch faces the start
(first column) of the next. Output: OBJ with one group per base patch (`patch_1`, ...) and the
blend surface (`blend`); --control-mesh writes the blend control mesh with its `t interval`
tags (its outer ring is the extension layer).

Examples:
  subsurf blend examples/patches/blend3.json -o blend3.obj
  subsurf blend examples/patches/blend5.json -o blend5.obj --levels 6 \\
      --control-mesh blend5-control.obj";

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
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// The name of the input in messages: the file name as given, or `<stdin>` for `-`.
pub fn input_name(path: &Path) -> String {
    if path == Path::new("-") {
        "<stdin>".to_owned()
    } else {
        path.display().to_string()
    }
}

/// The surfaces of `items` (polynomial or rational), or an error naming the item that is a
/// curve.
pub fn patches(items: &[SourcedGeometry]) -> Result<Vec<Surface>> {
    items
        .iter()
        .map(|g| match &g.geometry {
            Geometry::Surface(s) => Ok(s.clone()),
            Geometry::Curve(_) => bail!("{}: a curve; blending takes patches", g.label()),
        })
        .collect()
}

/// A library error, prefixed with the file position and name of the input item it is about
/// (the library numbers items from 0, as the JSON `[i]` positions do), or else with the
/// input's name.
pub fn explain(e: BlendError, items: &[SourcedGeometry], name: &str) -> anyhow::Error {
    match e.input_index().and_then(|i| items.get(i)) {
        Some(item) => anyhow::anyhow!("{}: {e}", item.label()),
        None => anyhow::anyhow!("{name}: {e}"),
    }
}

/// Peak bytes per face of the last refined level's bound, output included (measured on
/// the bundled examples at levels 5–7, peak RSS of a release build: 144–189; see
/// RELIABILITY.md).
const BYTES_PER_REFINED_FACE: u64 = 256;

/// Peak bytes per sample of the tessellated base patches and curves, output included
/// (measured: 52 between `--samples 128` and `256`).
const BYTES_PER_SAMPLE: u64 = 96;

/// The process's own memory besides the job (code, threads, allocator), charged once.
const BASE_BYTES: u64 = 8 << 20;

/// The samples of the tessellated `patches` at `per_span` segments per knot span (the
/// `--samples` of `blend` and `fill`): `(s_u N + 1)(s_v N + 1)` per patch, `s` its spans.
pub fn sample_points(patches: &[Surface], per_span: u32) -> u64 {
    let n = u64::from(per_span);
    let along = |k: &subsurf::nurbs::KnotVector| {
        let (a, b) = k.domain();
        let mut spans = 0u64;
        let t = k.as_slice();
        for w in t.windows(2) {
            if w[0] < w[1] && w[0] >= a && w[1] <= b {
                spans += 1;
            }
        }
        spans.max(1).saturating_mul(n).saturating_add(1)
    };
    patches
        .iter()
        .map(|s| {
            let (ku, kv) = match s {
                Surface::BSpline(s) => (s.knots_u(), s.knots_v()),
                Surface::Nurbs(s) => (s.knots_u(), s.knots_v()),
            };
            along(ku).saturating_mul(along(kv))
        })
        .fold(0, u64::saturating_add)
}

/// Refuses a `blend` or `fill` (`what`) whose refinement of `control` to `levels` plus
/// `samples` tessellation samples would exceed `max` (`--max-memory`, else the memory
/// available): the last level has at most `S · 4^(L−1)` faces (`S` the control mesh's
/// face corners, one quad each after a step; skirt removal only drops faces), charged at
/// [`BYTES_PER_REFINED_FACE`] each, every sample at [`BYTES_PER_SAMPLE`], plus
/// [`BASE_BYTES`].
pub fn check_memory(
    name: &str,
    what: &str,
    control: &PolyMesh,
    levels: u32,
    samples: u64,
    max: Option<u64>,
) -> Result<()> {
    let corners = control.face_verts().len() as u64;
    let faces = if levels == 0 {
        control.num_faces() as u64
    } else {
        corners.saturating_mul(4u64.saturating_pow(levels - 1))
    };
    let estimate = faces
        .saturating_mul(BYTES_PER_REFINED_FACE)
        .saturating_add(samples.saturating_mul(BYTES_PER_SAMPLE))
        .saturating_add(BASE_BYTES);
    crate::memory::check(
        name,
        &format!("{what} with {levels} levels"),
        estimate,
        max,
        "use fewer --levels or --samples",
    )
}

/// Runs `subsurf blend`.
pub fn run(args: &BlendArgs) -> Result<()> {
    let out = Output::new(&args.output);
    out.check()?;
    let control_out = args.control_mesh.as_deref().map(Output::new);
    if let Some(c) = &control_out {
        c.check()?;
    }
    let name = input_name(&args.input);
    let items = read_geometry(&args.input)?;
    let patches = patches(&items)?;
    let control = blend_control_mesh(&patches).map_err(|e| explain(e, &items, &name))?;
    check_memory(
        &name,
        "blending",
        &control.mesh,
        args.levels,
        sample_points(&patches, args.samples),
        args.max_memory,
    )?;
    let b = blend(&patches, args.levels).map_err(|e| explain(e, &items, &name))?;
    let surface = b.surface().map_err(|e| explain(e, &items, &name))?;
    let tessellated = patches
        .iter()
        .map(|s| s.grid(args.samples as usize))
        .collect::<Result<Vec<PolyMesh>, _>>()
        .with_context(|| name.clone())?;
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
