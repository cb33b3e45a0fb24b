//! `subsurf nurbs`: read NURBS curves and surfaces (JSON or OBJ free-form), print a summary,
//! convert between the two formats, or sample them as OBJ polylines and quad grids.

use anyhow::{bail, Result};
use subsurf::io::write_groups_obj;
use subsurf::io::{geometry_to_string, read_geometry, GeometryFormat};
use subsurf::mesh::PolyMesh;
use subsurf::nurbs::SourcedGeometry;
use subsurf::nurbs::{sample_count, Curve, Geometry, KnotVector, Surface};

use crate::output::Output;
use crate::NurbsArgs;

/// Runs `subsurf nurbs`.
pub fn run(args: &NurbsArgs) -> Result<()> {
    let format = match &args.output {
        Some(path) if args.sample.is_none() && path.as_os_str() != "-" => {
            Some(GeometryFormat::from_path(path).ok_or_else(|| {
                anyhow::anyhow!(
                    "cannot write {}: the output needs the extension .json or .obj",
                    path.display()
                )
            })?)
        }
        _ => None,
    };
    if let Some(path) = &args.output {
        if args.sample.is_some()
            && path.as_os_str() != "-"
            && GeometryFormat::from_path(path) != Some(GeometryFormat::Obj)
        {
            bail!(
                "cannot write {}: --sample writes OBJ (polylines and quads); use a .obj name",
                path.display()
            );
        }
        Output::new(path).check()?;
    }
    let items = read_geometry(&args.input)?;
    let Some(path) = &args.output else {
        crate::output::print(&summary(&items))?;
        return Ok(());
    };
    if let Some(n) = args.sample {
        let name = if args.input.as_os_str() == "-" {
            "<stdin>".to_string()
        } else {
            args.input.display().to_string()
        };
        crate::memory::check(
            &name,
            &format!("sampling at {n} segments per knot span"),
            sample_bytes(&items, n as usize),
            args.max_memory,
            "use a lower --sample",
        )?;
    }
    let out = Output::new(path);
    let text = match (args.sample, format) {
        (Some(n), _) => sampled_obj(&items, n as usize)?,
        (None, Some(f)) => geometry_to_string(&geometry(&items), f),
        // `-o -` without --sample: JSON on standard output.
        (None, None) => geometry_to_string(&geometry(&items), GeometryFormat::Json),
    };
    out.write(|w| w.write_all(text.as_bytes()))
}

fn geometry(items: &[SourcedGeometry]) -> Vec<Geometry> {
    items.iter().map(|g| g.geometry.clone()).collect()
}

/// One line per curve or surface.
fn summary(items: &[SourcedGeometry]) -> String {
    let mut s = String::new();
    for g in items {
        let line = match &g.geometry {
            Geometry::Curve(c) => {
                let (k, n, rational) = match c {
                    Curve::BSpline(c) => (c.knots(), c.points().len(), false),
                    Curve::Nurbs(c) => (c.knots(), c.points().len(), true),
                };
                format!(
                    "curve: {}degree {}, {n} control points, {}",
                    if rational { "rational, " } else { "" },
                    k.degree(),
                    describe(k)
                )
            }
            Geometry::Surface(srf) => {
                let (ku, kv, (nu, nv), rational) = match srf {
                    Surface::BSpline(s) => (s.knots_u(), s.knots_v(), s.size(), false),
                    Surface::Nurbs(s) => (s.knots_u(), s.knots_v(), s.size(), true),
                };
                format!(
                    "surface: {}degree {} x {}, {nu} x {nv} control points, u {}, v {}",
                    if rational { "rational, " } else { "" },
                    ku.degree(),
                    kv.degree(),
                    describe(ku),
                    describe(kv)
                )
            }
        };
        s.push_str(&format!("{}: {line}\n", g.label()));
    }
    s
}

/// Domain, closedness and clamping of a knot vector.
fn describe(k: &KnotVector) -> String {
    let (a, b) = k.domain();
    let kind = if k.is_periodic() {
        "closed"
    } else if k.is_clamped() {
        "clamped"
    } else {
        "unclamped"
    };
    format!("domain [{a}, {b}], {kind}")
}

/// Peak bytes per sample point of `--sample`: its position (24), a grid quad's indices and
/// offset (20), and the OBJ text of both (a `v` line of up to 3 × 24 digits, an `f` line of
/// four indices), all held until the file is written (measured peak about 160 bytes per point
/// at 1.7 M points).
const SAMPLE_BYTES: u64 = 256;

/// Estimated peak memory of [`sampled_obj`] with `per_span` segments per knot span.
fn sample_bytes(items: &[SourcedGeometry], per_span: usize) -> u64 {
    items
        .iter()
        .map(|g| match &g.geometry {
            Geometry::Curve(c) => {
                let k = match c {
                    Curve::BSpline(c) => c.knots(),
                    Curve::Nurbs(c) => c.knots(),
                };
                sample_count(k, per_span)
            }
            Geometry::Surface(s) => {
                let (ku, kv) = match s {
                    Surface::BSpline(s) => (s.knots_u(), s.knots_v()),
                    Surface::Nurbs(s) => (s.knots_u(), s.knots_v()),
                };
                sample_count(ku, per_span).saturating_mul(sample_count(kv, per_span))
            }
        })
        .fold(0u64, u64::saturating_add)
        .saturating_mul(SAMPLE_BYTES)
}

/// Curves as OBJ polylines (`l`) and surfaces as quad grids, `per_span` segments per knot
/// span, each element in its own group (`g NAME`, the element's name or `elementN`).
fn sampled_obj(items: &[SourcedGeometry], per_span: usize) -> Result<String> {
    let mut grids: Vec<(String, PolyMesh)> = Vec::new();
    let mut polylines: Vec<(String, Vec<[f64; 3]>)> = Vec::new();
    for (n, g) in items.iter().enumerate() {
        let group = match &g.name {
            Some(name) if !name.trim().is_empty() => {
                name.split_whitespace().collect::<Vec<_>>().join("_")
            }
            _ => format!("element{}", n + 1),
        };
        match &g.geometry {
            Geometry::Curve(c) => polylines.push((group, c.polyline(per_span)?)),
            Geometry::Surface(s) => grids.push((group, s.grid(per_span)?)),
        }
    }
    let groups: Vec<(String, &PolyMesh)> = grids.iter().map(|(n, m)| (n.clone(), m)).collect();
    let mut bytes = Vec::new();
    write_groups_obj(
        &mut bytes,
        Some("subsurf nurbs --sample: curves as polylines, surfaces as quads"),
        &groups,
        &polylines,
    )?;
    Ok(String::from_utf8(bytes)?)
}
