//! `subsurf render`: draw the exact limit surface (or a refined mesh) to a PNG with the
//! library's software rasteriser.

use std::path::Path;

use anyhow::{bail, Context, Result};
use subsurf::io::Up;
use subsurf::limit::{BuildError, LimitSurface};
use subsurf::mesh::{Options, PolyMesh};
use subsurf::render::CurvatureKind;
use subsurf::render::{render_detailed, write_png, Geometry, Paint, Render, RenderError, Shading};
use subsurf::Scheme;

use crate::input::Input;
use crate::output::Output;
use crate::{RenderArgs, SchemeKind};

/// Default samples per base edge of the limit surface.
const DEFAULT_RATE: u32 = 16;
/// Without --limit-rate, the default rate is lowered so that about this many polygons are
/// drawn at most (plenty for any picture size).
const DEFAULT_BUDGET: u64 = 4 << 20;

/// Runs `subsurf render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    if args.scheme_kind == Some(SchemeKind::Nurss) {
        super::adjustable::usage_error(
            "render draws the catmull-clark, adjustable (--c), loop and bilinear surfaces; \
             sample the NURSS surface with tessellate --scheme nurss",
        );
    }
    super::adjustable::check_surface_flags(args.scheme_kind, &args.adjust);
    let scheme = match args.scheme_kind {
        Some(SchemeKind::Loop) => Scheme::Loop,
        Some(SchemeKind::Bilinear) => Scheme::Bilinear,
        _ => Scheme::CatmullClark,
    };
    check_png(&args.output)?;
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
    let mut opts = Render {
        scheme,
        ..render_options(args)
    };
    if args.level.is_none() && args.limit_rate.is_none() {
        let rate = default_rate(&input.obj.mesh, scheme);
        if rate < DEFAULT_RATE && !args.quiet {
            crate::output::eprint_line(&format!(
                "note: {}: the mesh is large; drawing its limit surface at rate {rate} \
                 (--limit-rate sets it)",
                input.name
            ));
        }
        opts.geometry = Geometry::Limit { rate };
    }
    let refined = mixed_refined(args, &input, options, &mut opts)?;
    let mesh = refined.as_ref().unwrap_or(&input.obj.mesh);
    let what = match opts.geometry {
        Geometry::Level(l) => format!("drawing level {l}"),
        Geometry::Limit { rate } => format!("drawing the limit surface at rate {rate}"),
    };
    let estimate = estimate_memory(mesh, &options, &opts);
    let drawing = drawing_memory(mesh, &opts);
    // The picture or the geometry: whichever needs the most is the one to reduce.
    let pixels = u64::from(opts.width) * u64::from(opts.height) * BYTES_PER_PIXEL;
    let hint = match opts.geometry {
        _ if pixels >= estimate / 2 => "use a smaller --size",
        Geometry::Level(_) => "use a lower --level",
        Geometry::Limit { .. } => "use a lower --limit-rate",
    };
    crate::memory::check(&input.name, &what, estimate, args.max_memory, hint)?;
    // The surface is built within what the drawing leaves; a refusal while it is built or
    // before it is evaluated is told against the whole limit, as the check above.
    let limit = args.max_memory.or_else(crate::memory::available);
    opts.surface_memory = limit.map(|limit| limit.saturating_sub(drawing));
    let too_large = |needs| {
        crate::memory::too_large(
            &input.name,
            &what,
            needs,
            limit.unwrap_or(0),
            args.max_memory.is_some(),
            hint,
        )
    };
    let r = match render_detailed(mesh, &options, &opts) {
        Ok(r) => r,
        Err(RenderError::SurfaceMemory { estimate, .. }) => {
            return Err(too_large((estimate.saturating_add(drawing), false)));
        }
        Err(RenderError::Build(BuildError::TooLarge { limit, .. })) => {
            return Err(too_large((limit.saturating_add(drawing), true)));
        }
        Err(e) => return Err(e).with_context(|| input.name.clone()),
    };
    if let (Some((lo, hi)), false) = (r.curvature_range, args.quiet) {
        crate::output::eprint_line(&format!(
            "note: {}: {} curvature colour range {lo:.6e} .. {hi:.6e}",
            input.name,
            args.curvature.as_deref().unwrap_or_default()
        ));
    }
    out.write(|w| write_png(w, &r.image))
}

/// With --c, the mixed surface is drawn as the limit of the c-refined mesh: that mesh, with
/// the limit rate of `opts` divided as its faces are (`None` without --c).
fn mixed_refined(
    args: &RenderArgs,
    input: &Input,
    options: Options,
    opts: &mut Render,
) -> Result<Option<PolyMesh>> {
    let Some(m) = super::adjustable::for_surface(&args.adjust) else {
        return Ok(None);
    };
    if args.level.is_some() {
        super::adjustable::usage_error(
            "--c draws the mixed limit surface; it does not combine with --level",
        );
    }
    if let Geometry::Limit { rate } = opts.geometry {
        let rate = super::adjustable::refined_rate(rate, m.steps);
        opts.geometry = Geometry::Limit { rate };
    }
    Ok(Some(super::adjustable::refined_mesh(input, options, m)?))
}

/// Peak bytes per drawn vertex (measured: 307 at 6 million, with exact limit normals).
const BYTES_PER_VERTEX: u64 = 320;
/// Bytes per pixel (colour, depth and the PNG encoder's buffers; measured: 7).
const BYTES_PER_PIXEL: u64 = 16;

/// Estimated peak memory of drawing `mesh` with `opts`, before the surface is built: the
/// picture, the drawn vertices, and the exact limit surface without its configurations
/// (the library charges those as it builds, see `Render::surface_memory`) or the
/// refinement for `--level`.
fn estimate_memory(mesh: &subsurf::mesh::PolyMesh, options: &Options, opts: &Render) -> u64 {
    let geometry = match opts.geometry {
        Geometry::Limit { .. } => LimitSurface::estimate_build_memory(mesh),
        Geometry::Level(0) => 0,
        Geometry::Level(l) => subsurf::estimate_memory(
            mesh,
            &subsurf::SubdivideOptions {
                levels: l,
                options: *options,
                scheme: opts.scheme,
                ..subsurf::SubdivideOptions::default()
            },
        ),
    };
    // A texture on the limit: the limit surface of the texture coordinates' value mesh
    // (the mesh's faces, at least its vertices: estimated as the mesh's own).
    let texture = match (opts.paint, opts.geometry) {
        (Paint::Checker { .. }, Geometry::Limit { .. }) => {
            LimitSurface::estimate_build_memory(mesh)
        }
        _ => 0,
    };
    (drawing_memory(mesh, opts).saturating_add(geometry)).saturating_add(texture)
}

/// Peak memory of the picture and of the drawn vertices of `mesh` with `opts` (also
/// `subsurf g2`'s pictures).
pub(crate) fn drawing_memory(mesh: &subsurf::mesh::PolyMesh, opts: &Render) -> u64 {
    let pixels = u64::from(opts.width) * u64::from(opts.height) * BYTES_PER_PIXEL;
    let vertices = match opts.geometry {
        Geometry::Limit { rate } => crate::memory::tessellation_vertices(mesh, rate),
        // The first level has a quad per face corner, or four triangles per triangle.
        Geometry::Level(l) => match opts.scheme {
            Scheme::Loop => 4 * mesh.num_faces() as u64,
            _ => mesh.face_verts().len() as u64,
        }
        .checked_shl(2 * l.saturating_sub(1))
        .unwrap_or(u64::MAX),
    };
    pixels.saturating_add(vertices.saturating_mul(BYTES_PER_VERTEX))
}

/// The library's options from the command line.
fn render_options(args: &RenderArgs) -> Render {
    let geometry = match args.level {
        Some(l) => Geometry::Level(l),
        None => Geometry::Limit {
            rate: args.limit_rate.unwrap_or(DEFAULT_RATE),
        },
    };
    let paint = match (args.zebra, args.curvature.as_deref(), args.faces) {
        _ if args.texture.is_some() => Paint::Checker {
            squares: args.squares,
        },
        (true, _, _) => Paint::Zebra,
        (_, Some("gauss"), _) => Paint::Curvature(CurvatureKind::Gauss),
        (_, Some("mean"), _) => Paint::Curvature(CurvatureKind::Mean),
        (_, Some(_), _) => Paint::Curvature(CurvatureKind::Max),
        (_, None, true) => Paint::Faces,
        _ => Paint::Plain,
    };
    Render {
        width: args.size.0,
        height: args.size.1,
        geometry,
        shading: if args.shade == "flat" {
            Shading::Flat
        } else {
            Shading::Smooth
        },
        paint,
        control_mesh: args.control_mesh,
        view: args.view,
        up: if args.up == "y" { Up::Y } else { Up::Z },
        zoom: args.zoom,
        curvature_range: args.range,
        ..Render::default()
    }
}

/// [`DEFAULT_RATE`], or less (at least 1) for meshes that would draw more than
/// [`DEFAULT_BUDGET`] polygons with `scheme`.
fn default_rate(mesh: &subsurf::mesh::PolyMesh, scheme: Scheme) -> u32 {
    // Polygons per unit of rate²: 1 per quad (and per Loop triangle), n/4 per n-gon (n
    // sub-faces of (rate/2)²).
    let per_rate2: f64 = mesh
        .faces()
        .map(|f| {
            if f.len() == 4 || scheme == Scheme::Loop {
                1.0
            } else {
                f.len() as f64 / 4.0
            }
        })
        .sum();
    if per_rate2 <= 0.0 {
        return DEFAULT_RATE;
    }
    let r = (DEFAULT_BUDGET as f64 / per_rate2).sqrt().floor();
    (r as u32).clamp(1, DEFAULT_RATE)
}

/// Only PNG is written: to `-` (standard output), a `.png` file (any case) or a name
/// without an extension (a device such as `/dev/stdout`).
fn check_png(path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        None | Some("png") => Ok(()),
        Some(other) => bail!(
            "cannot write {}: unknown picture format '.{other}' (only .png is written)",
            path.display()
        ),
    }
}

/// Parses `A,B` (two finite numbers), as in `--view 30,20` or `--range -1,1`.
pub fn parse_pair(s: &str) -> Result<(f64, f64), String> {
    let bad = || format!("'{s}' is not two numbers separated by a comma (e.g. 30,20)");
    let (a, b) = s.split_once(',').ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    if !(a.is_finite() && b.is_finite()) {
        return Err(format!("'{s}': the numbers must be finite"));
    }
    Ok((a, b))
}

/// Parses a zoom factor (0.01 to 1000).
pub fn parse_zoom(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(z) if (0.01..=1000.0).contains(&z) => Ok(z),
        _ => Err(format!("'{s}' is not a zoom factor from 0.01 to 1000")),
    }
}

/// Parses `WxH` (each side 16 to 8192 pixels), as in `--size 800x600`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("'{s}' is not a size WxH (e.g. 800x600)");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(format!("'{s}': each side must be 16 to 8192 pixels"));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_pairs_and_sizes() {
        assert_eq!(parse_pair("30,20"), Ok((30.0, 20.0)));
        assert_eq!(parse_pair("-30, -5.5"), Ok((-30.0, -5.5)));
        assert!(parse_pair("30").is_err());
        assert!(parse_pair("a,b").is_err());
        assert!(parse_pair("inf,0").is_err());
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_size("200X150"), Ok((200, 150)));
        assert!(parse_size("800").is_err());
        assert!(parse_size("8x600").is_err());
        assert!(parse_size("0x0").is_err());
        assert!(parse_size("-1x5").is_err());
    }

    #[test]
    fn the_default_rate_drops_for_large_meshes() {
        use subsurf::mesh::PolyMesh;
        let grid = |n: u32| {
            let p: Vec<[f64; 3]> = (0..=n)
                .flat_map(|j| (0..=n).map(move |i| [f64::from(i), f64::from(j), 0.0]))
                .collect();
            let f: Vec<[u32; 4]> = (0..n)
                .flat_map(|j| {
                    (0..n).map(move |i| {
                        let a = j * (n + 1) + i;
                        [a, a + 1, a + n + 2, a + n + 1]
                    })
                })
                .collect();
            PolyMesh::from_faces(p, &f).expect("a valid grid")
        };
        let cc = Scheme::CatmullClark;
        assert_eq!(default_rate(&grid(4), cc), DEFAULT_RATE);
        // 102 400 quads: 4 Mi / 102 400 = 40.96 polygons each, rate 6.
        assert_eq!(default_rate(&grid(320), cc), 6);
        assert_eq!(default_rate(&PolyMesh::default(), cc), DEFAULT_RATE);
    }

    #[test]
    fn only_png() {
        assert!(check_png(Path::new("a.png")).is_ok());
        assert!(check_png(Path::new("dir/A.PNG")).is_ok());
        assert!(check_png(Path::new("-")).is_ok());
        let e = check_png(Path::new("a.jpg")).unwrap_err().to_string();
        assert!(e.contains("'.jpg'") && e.contains(".png"), "{e}");
        assert!(
            check_png(Path::new("noext")).is_ok(),
            "a name without an extension is a PNG"
        );
    }
}
