//! `subsurf g2`: the Catmull-Clark surface with G2 caps at the extraordinary vertices
//! (seed 003): a tessellation (OBJ) or the patches' Bézier control points (JSON), and
//! optionally the continuity report; with `--c C [--adjust-steps K]` of the mixed
//! (shape-adjustable) surface instead of Catmull-Clark.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;
use subsurf::g2cap::{
    continuity_report, patches_json, tessellate, to_iges, G2Surface, G2SurfaceOptions,
};
use subsurf::io::obj::{write_obj, WriteOptions};
use subsurf::limit::{Derivatives, EvalError, SurfacePoint};
use subsurf::mesh::Options;
use subsurf::render::{
    curvature::CurvatureKind, render_surface, write_png, Geometry, Paint, Render, SampledSurface,
};
use subsurf::{estimate_memory, SubdivideOptions};

use crate::input::Input;
use crate::output::Output;
use crate::{AdjustArgs, SchemeArgs};

pub const G2_EXAMPLES: &str = "\
Every interior extraordinary vertex with no crease nearby (valence 3 to 16, and the centre of
every n-gon) gets a cap of n bi-septic Bezier patches that join each other and the
surrounding bicubic B-spline patches with curvature continuity (G2); vertices on boundaries
or creases keep Catmull-Clark (listed with --report). OBJ output is a tessellation, N x N
quads per face (ceil(N/2) per sub-face of an n-gon), with normals; JSON output lists every
patch's control points (schema in the README); .igs/.iges output writes the same patches as
IGES 5.3 rational B-spline surfaces (entity 128). --report prints, for every cap boundary, the
largest position gap, normal angle and relative jump of the normal curvature across it, for
the G2 surface and for Catmull-Clark (to standard error when the surface goes to standard
output). A .png output draws the G2 surface (the same renderer as 'subsurf render'), plain,
with --zebra reflection lines or --curvature gauss|mean|max from its exact derivatives;
--compare draws plain Catmull-Clark instead, for side-by-side pictures.
With --c C the surface is the mixed (shape-adjustable) one: K steps (--adjust-steps, default
1) of the adjustable scheme with parameter C, then Catmull-Clark, so that outside the caps it
is the bicubic B-spline of the C-refined mesh; the caps join it G2, and the report's and
--compare's Catmull-Clark is that mixed surface without caps. --c 0.5 is plain Catmull-Clark.

Examples:
  subsurf g2 model.obj -o model-g2.obj --rate 16
  subsurf g2 model.obj -o model-g2.json
  subsurf g2 model.obj -o model-g2.igs
  subsurf g2 model.obj -o model-g2.obj --report
  subsurf g2 model.obj -o model-g2-zebra.png --zebra --view 30,40
  subsurf g2 model.obj -o model-g2-tight.obj --c 0.3 --report";

/// Arguments of `subsurf g2`.
#[derive(Debug, Args)]
pub struct G2Args {
    /// Input OBJ file ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output file, .obj (tessellation), .json (control points), .igs/.iges (IGES entity
    /// 128 surfaces) or .png (picture) ('-' writes OBJ to
    /// standard output); written only when everything succeeded.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Segments per base edge of the tessellation.
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub rate: u32,
    /// Print the continuity report (G2 caps vs Catmull-Clark).
    #[arg(long)]
    pub report: bool,
    /// With a .png output: reflection lines.
    #[arg(long, conflicts_with = "curvature")]
    pub zebra: bool,
    /// With a .png output: colour by curvature (gauss, mean or max).
    #[arg(long, value_name = "KIND", value_parser = ["gauss", "mean", "max"])]
    pub curvature: Option<String>,
    /// With a .png output: camera azimuth and elevation in degrees.
    #[arg(long, value_name = "AZ,EL", value_parser = parse_view, allow_hyphen_values = true)]
    pub view: Option<(f64, f64)>,
    /// With a .png output: draw plain Catmull-Clark instead of the G2 surface.
    #[arg(long)]
    pub compare: bool,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Print no notes.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Obj,
    Json,
    Iges,
    Png,
}

fn parse_view(s: &str) -> Result<(f64, f64), String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not AZ,EL"))?;
    let parse = |x: &str| {
        x.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("'{x}' is not a number"))
    };
    Ok((parse(a)?, parse(e)?))
}

fn format(path: &Path) -> Result<Format> {
    if path == Path::new("-") {
        return Ok(Format::Obj);
    }
    match path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .as_deref()
    {
        Some("obj") => Ok(Format::Obj),
        Some("json") => Ok(Format::Json),
        Some("igs" | "iges") => Ok(Format::Iges),
        Some("png") => Ok(Format::Png),
        _ => bail!(
            "cannot write {}: subsurf g2 writes .obj (tessellation), .json (control points), \
             .igs/.iges (IGES surfaces) or .png (picture)",
            path.display()
        ),
    }
}

/// Runs `subsurf g2`.
pub fn run(args: &G2Args) -> Result<()> {
    let fmt = format(&args.output)?;
    if fmt != Format::Png
        && (args.zebra || args.curvature.is_some() || args.view.is_some() || args.compare)
    {
        bail!("--zebra, --curvature, --view and --compare need a .png output");
    }
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input, None)?;
    let scheme = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    let mesh = &input.obj.mesh;
    let options = G2SurfaceOptions {
        scheme,
        levels: None,
    };
    // `--c` (validated by clap: in [0, 1], else a usage error) with K = 1 by default.
    let mixed = super::adjustable::for_surface(&args.adjust);
    let surface = match mixed {
        Some(m) => {
            check_memory(mesh, scheme, m.steps)
                .with_context(|| format!("{}: --adjust-steps {}", input.name, m.steps))?;
            G2Surface::new_mixed(mesh, &options, m)
        }
        None => G2Surface::new(mesh, &options),
    }
    .with_context(|| input.name.clone())?;
    let adjust_flags = mixed.map_or(String::new(), |m| {
        format!(" --c {} --adjust-steps {}", m.scheme.c(), m.steps)
    });
    if !args.quiet && !surface.uncapped().is_empty() {
        eprintln!(
            "note: {}: {} extraordinary vertices or face centres keep Catmull-Clark \
             (boundary, crease or feature nearby)",
            input.name,
            surface.uncapped().len()
        );
    }
    match fmt {
        Format::Obj => {
            let t = tessellate(&surface, mesh, args.rate).with_context(|| input.name.clone())?;
            let poly = t.to_polymesh().with_context(|| input.name.clone())?;
            let comment = format!(
                "subsurf g2 --rate {}{} {}: {} caps",
                args.rate,
                adjust_flags,
                input.name,
                surface.caps().len()
            );
            out.write(|mut w| {
                write_obj(
                    &mut w,
                    &poly,
                    &WriteOptions {
                        normals: Some(&t.normals),
                        scheme: None,
                        comment: Some(&comment),
                    },
                )
            })?;
        }
        Format::Png => {
            let mut opts = Render {
                geometry: Geometry::Limit { rate: args.rate },
                ..Default::default()
            };
            if args.zebra {
                opts.paint = Paint::Zebra;
            }
            opts.paint = match args.curvature.as_deref() {
                Some("gauss") => Paint::Curvature(CurvatureKind::Gauss),
                Some("mean") => Paint::Curvature(CurvatureKind::Mean),
                Some("max") => Paint::Curvature(CurvatureKind::Max),
                _ => opts.paint,
            };
            if let Some(v) = args.view {
                opts.view = v;
            }
            let g2: &dyn SampledSurface = &surface;
            let uncapped = Uncapped(&surface);
            let drawn_surface = match (args.compare, surface.mixed().is_some()) {
                (false, _) => Some(g2),
                (true, true) => Some(&uncapped as &dyn SampledSurface),
                (true, false) => None,
            };
            let drawn = render_surface(mesh, &scheme, &opts, drawn_surface)
                .with_context(|| input.name.clone())?;
            out.write(|w| write_png(w, &drawn.image))?;
        }
        Format::Json => {
            let doc = patches_json(&surface, mesh).with_context(|| input.name.clone())?;
            let text = doc.to_json();
            out.write(|w| writeln!(w, "{text}"))?;
        }
        Format::Iges => {
            let doc = patches_json(&surface, mesh).with_context(|| input.name.clone())?;
            let name = args
                .output
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let text = to_iges(&doc, &name);
            out.write(|w| w.write_all(text.as_bytes()))?;
        }
    }
    if args.report {
        let r = continuity_report(&surface, 24).with_context(|| input.name.clone())?;
        let text = format!(
            "{}{}: {} caps, {} left with Catmull-Clark; 24 samples per boundary\n{r}",
            input.name,
            if mixed.is_some() {
                format!(
                    " ({}; the Catmull-Clark rows are the mixed surface without caps)",
                    adjust_flags.trim()
                )
            } else {
                String::new()
            },
            surface.caps().len(),
            surface.uncapped().len()
        );
        if matches!(out, Output::Stdout) {
            eprint!("{text}");
        } else {
            print!("{text}");
        }
        for u in surface.uncapped() {
            let what = match (u.vertex, u.face) {
                (Some(v), _) => format!("vertex {v}"),
                (None, Some(f)) => format!("centre of face {f}"),
                _ => "?".into(),
            };
            let line = format!("  {what} (valence {}): {}", u.valence, u.reason);
            if matches!(out, Output::Stdout) {
                eprintln!("{line}");
            } else {
                println!("{line}");
            }
        }
    }
    Ok(())
}

/// The surface without caps (`--compare` with `--c`: the mixed surface).
struct Uncapped<'a>(&'a G2Surface);

impl SampledSurface for Uncapped<'_> {
    fn sample(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.0.eval_uncapped(p)
    }
}

/// Refuses `--adjust-steps` whose refined mesh would not fit in the available memory
/// (the estimate of `subsurf subdivide`).
fn check_memory(mesh: &subsurf::mesh::PolyMesh, scheme: Options, steps: u32) -> Result<()> {
    let opts = SubdivideOptions {
        levels: steps,
        scheme,
        keep_holes: true,
        ..SubdivideOptions::default()
    };
    let estimate = estimate_memory(mesh, &opts);
    match crate::memory::available() {
        Some(limit) if estimate > limit => Err(subsurf::Error::TooLarge {
            levels: steps,
            estimate,
            limit,
        }
        .into()),
        _ => Ok(()),
    }
}
