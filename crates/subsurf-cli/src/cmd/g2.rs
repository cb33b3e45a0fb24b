//! `subsurf g2`: the Catmull-Clark surface with G2 caps at the extraordinary vertices
//! ([Tang et al. 2017]): a tessellation (OBJ) or the patches' Bézier control points (JSON), and
//! optionally the continuity report; with `--c C [--adjust-steps K]` of the mixed
//! (shape-adjustable) surface instead of Catmull-Clark.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use subsurf::g2cap::{continuity_report, patches_json, to_iges, G2Surface, G2SurfaceOptions};
use subsurf::io::{write_tessellation, TessellationFormat, TessellationWriteOptions};
use subsurf::limit::{tessellate, Derivatives, EvalError, Surface, SurfacePoint};
use subsurf::mesh::Options;
use subsurf::render::{render_surface, write_png, CurvatureKind, Geometry, Paint, Render};
use subsurf::Scheme;
use subsurf::{estimate_memory, SubdivideOptions};

use crate::input::Input;
use crate::output::{formats, Format, Output};
use crate::{AdjustArgs, SchemeArgs};

pub const G2_EXAMPLES: &str = "\
Every interior extraordinary vertex with no crease nearby (valence 3 to 16, and the centre of
every n-gon) gets a cap of n bi-septic Bezier patches that join each other and the
surrounding bicubic B-spline patches with curvature continuity (G2); vertices on boundaries
or creases keep Catmull-Clark (listed with --report). OBJ output is a tessellation, N x N
quads per face (ceil(N/2) per sub-face of an n-gon), with normals; JSON output lists every
patch's control points (schema in docs/adjustable-g2.md); .igs/.iges output writes the same
patches as IGES 5.3 rational B-spline surfaces (entity 128). --report prints, for every cap boundary, the
largest position gap, normal angle and relative jump of the normal curvature across it, for
the G2 surface and for Catmull-Clark (to standard error when the surface goes to standard
output). A .png output draws the G2 surface (the same renderer as 'subsurf render'), plain,
with --zebra reflection lines or --curvature gauss|mean|max from its exact derivatives;
--compare draws plain Catmull-Clark instead, for side-by-side pictures (give both the same
--range, so that one colour means one curvature in both).
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
    /// With --curvature: fixed colour range instead of the automatic one (give both pictures
    /// of a comparison the same range).
    #[arg(long, value_name = "MIN,MAX", requires = "curvature", allow_hyphen_values = true, value_parser = super::render::parse_pair)]
    pub range: Option<(f64, f64)>,
    /// With a .png output: magnify the fitted view F times around the picture's centre.
    #[arg(long, value_name = "F", default_value_t = 1.0, value_parser = super::render::parse_zoom)]
    pub zoom: f64,
    /// With a .png output: picture size in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    #[command(flatten)]
    pub scheme: SchemeArgs,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
    /// Print no notes.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Peak bytes per sample of an OBJ tessellation, writing included (measured between rates
/// 512 and 1024 on the cube: 168).
const BYTES_PER_SAMPLE: u64 = 208;

/// Peak bytes per drawn vertex of a picture beyond `subsurf render`'s estimate (measured
/// between rates 256 and 512 on the cube: 312 per vertex against render's 320; on poles of
/// valence 500 more, with the shared region's evaluation).
const PNG_EXTRA_PER_SAMPLE: u64 = 96;

/// Bytes of the G2 surface per square of its isolation level (a bicubic Bézier patch) and
/// per cap patch (bi-septic), held whatever the output.
const SURFACE_BYTES: (u64, u64) = (512, 2048);

/// Peak bytes of a JSON document per square and per cap patch (measured: 2 160 per square on
/// a closed 400 × 400 quad torus, about 23 000 per cap patch on the two-pole meshes).
const JSON_BYTES: (u64, u64) = (3072, 32768);

/// The same for an IGES document (measured: 5 500 and about 39 000).
const IGES_BYTES: (u64, u64) = (8192, 49152);

/// The memory that the output sizes, for `fmt`: the OBJ tessellation's samples or the
/// picture's drawn vertices and pixels (as `subsurf render` estimates them) at `rate`, or,
/// once `surface` is built, the JSON or IGES document of its patches. An upper bound of
/// the measured peak beyond the limit surface (RELIABILITY.md). `size`: the picture's.
fn output_memory(
    mesh: &subsurf::mesh::PolyMesh,
    (rate, size): (u32, (u32, u32)),
    fmt: Format,
    patches: (u64, u64),
) -> u64 {
    let samples = crate::memory::tessellation_vertices(mesh, rate);
    let per = |(square, cap): (u64, u64)| {
        patches
            .0
            .saturating_mul(square)
            .saturating_add(patches.1.saturating_mul(cap))
    };
    match fmt {
        Format::Png => super::render::drawing_memory(
            mesh,
            &Render {
                geometry: Geometry::Limit { rate },
                width: size.0,
                height: size.1,
                ..Default::default()
            },
        )
        .saturating_add(samples.saturating_mul(PNG_EXTRA_PER_SAMPLE)),
        Format::Json => per(JSON_BYTES),
        Format::Iges => per(IGES_BYTES),
        // A tessellation.
        _ => samples.saturating_mul(BYTES_PER_SAMPLE),
    }
}

/// Squares of the isolation level `l` on `mesh`: `4^l` per quad, `n 4^(l−1)` per `n`-gon
/// (an upper bound of the bicubic patches).
fn squares(mesh: &subsurf::mesh::PolyMesh, l: u32) -> u64 {
    let per_quad = 4u64.saturating_pow(l);
    mesh.faces()
        .map(|f| match f.len() {
            4 => per_quad,
            n => (n as u64).saturating_mul(per_quad / 4),
        })
        .fold(0u64, u64::saturating_add)
}

/// The squares and cap patches of the built `surface`.
fn patch_counts(surface: &G2Surface, mesh: &subsurf::mesh::PolyMesh) -> (u64, u64) {
    let caps = surface.caps().iter().map(|c| c.slots.len() as u64).sum();
    (squares(mesh, surface.levels()), caps)
}

/// Upper bounds of [`patch_counts`] before the surface is built: the isolation level the
/// library picks (2, 3 with n-gons, at least `K + 1` with `--adjust-steps K`) and a cap of
/// `n` patches at every vertex of valence 3 to 16 but 4 and every n-gon's centre.
fn patch_bound(mesh: &subsurf::mesh::PolyMesh, steps: Option<u32>) -> (u64, u64) {
    let ngons = mesh.faces().any(|f| f.len() != 4);
    let l = if ngons { 3 } else { 2 }.max(steps.map_or(0, |k| k.saturating_add(1)));
    let mut valence = vec![0u64; mesh.num_vertices()];
    for f in mesh.faces() {
        for &v in f {
            valence[v as usize] += 1;
        }
    }
    let max = subsurf::g2cap::MAX_CAP_VALENCE as u64;
    let at_vertices: u64 = valence
        .iter()
        .filter(|&&n| (3..=max).contains(&n) && n != 4)
        .sum();
    let at_centres: u64 = mesh
        .faces()
        .map(|f| f.len() as u64)
        .filter(|&n| n != 4 && n <= max)
        .sum();
    (squares(mesh, l), at_vertices + at_centres)
}

/// The G2 surface's own patches and the output, for `patches` (squares, cap patches).
fn job_memory(
    mesh: &subsurf::mesh::PolyMesh,
    rate: (u32, (u32, u32)),
    fmt: Format,
    patches: (u64, u64),
) -> u64 {
    patches
        .0
        .saturating_mul(SURFACE_BYTES.0)
        .saturating_add(patches.1.saturating_mul(SURFACE_BYTES.1))
        .saturating_add(output_memory(mesh, rate, fmt, patches))
}

/// What the job does and what to do when it does not fit, for messages.
fn describe(args: &G2Args, fmt: Format) -> (String, &'static str) {
    match fmt {
        Format::Png => (
            format!("drawing the G2 surface at rate {}", args.rate),
            "use a lower --rate",
        ),
        Format::Json | Format::Iges => (
            "writing the G2 surface's patches".to_owned(),
            "the mesh has too many faces for this output",
        ),
        _ => (
            format!("tessellating the G2 surface at rate {}", args.rate),
            "use a lower --rate",
        ),
    }
}

/// Builds the G2 surface of `mesh` within the memory limit (`--max-memory`, else the
/// memory available), in three steps as the limit surface's guard (`memory::SurfaceGuard`):
/// refused before building when the surface without its configurations, the patches and
/// the output (upper bounds, [`patch_bound`]) would not fit; the Catmull-Clark surface's
/// build stopped as soon as its configurations would not; refused before any point is
/// evaluated or written when the built surface (evaluated as deep as `--rate` needs), its
/// patches and the output would not.
fn build_within(
    args: &G2Args,
    name: &str,
    mesh: &subsurf::mesh::PolyMesh,
    fmt: Format,
    options: &G2SurfaceOptions,
    mixed: Option<subsurf::Mixed>,
) -> Result<G2Surface> {
    let (what, hint) = describe(args, fmt);
    let limit = args.max_memory.or_else(crate::memory::available);
    let check = |estimate: u64| crate::memory::check(name, &what, estimate, args.max_memory, hint);
    let reserved = job_memory(
        mesh,
        (args.rate, args.size),
        fmt,
        patch_bound(mesh, mixed.map(|m| m.steps)),
    );
    check(subsurf::limit::LimitSurface::estimate_build_memory(mesh).saturating_add(reserved))?;
    if let Some(m) = mixed {
        check_memory(mesh, options.options, m.steps)
            .with_context(|| format!("{name}: --adjust-steps {}", m.steps))?;
    }
    let options = G2SurfaceOptions {
        scheme: mixed.map_or(Scheme::CatmullClark, Scheme::Adjustable),
        max_memory: limit.map(|l| l.saturating_sub(reserved)),
        ..*options
    };
    let surface = G2Surface::new(mesh, &options);
    let surface = match surface {
        Err(subsurf::g2cap::G2Error::TooLarge(e)) => anyhow::bail!(
            "{name}: {what} needs more than {}: {e}; {hint}",
            crate::memory::size(limit.unwrap_or(u64::MAX)),
        ),
        s => s.with_context(|| name.to_owned())?,
    };
    let actual = job_memory(
        mesh,
        (args.rate, args.size),
        fmt,
        patch_counts(&surface, mesh),
    );
    check(
        surface
            .limit()
            .estimate_memory(args.rate)
            .saturating_add(actual),
    )?;
    Ok(surface)
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

/// Runs `subsurf g2`.
pub fn run(args: &G2Args) -> Result<()> {
    let fmt = Format::of(&args.output, formats::G2, Format::Obj)?;
    if fmt != Format::Png
        && (args.zebra || args.curvature.is_some() || args.view.is_some() || args.compare)
    {
        bail!("--zebra, --curvature, --view and --compare need a .png output");
    }
    let out = Output::new(&args.output);
    out.check()?;
    let input = Input::read_surface(&args.input, args.max_memory)?;
    if !args.quiet {
        for w in input.warnings() {
            crate::output::eprint_line(&format!("warning: {w}"));
        }
    }
    let scheme = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    let mesh = &input.obj.mesh;
    let options = G2SurfaceOptions {
        options: scheme,
        ..Default::default()
    };
    // `--c` (validated by clap: in [0, 1], else a usage error) with K = 1 by default.
    let mixed = super::adjustable::for_surface(&args.adjust);
    let surface = build_within(args, &input.name, mesh, fmt, &options, mixed)?;
    let adjust_flags = mixed.map_or(String::new(), |m| {
        format!(" --c {} --adjust-steps {}", m.scheme.c(), m.steps)
    });
    if !args.quiet && !surface.uncapped().is_empty() {
        crate::output::eprint_line(&format!(
            "note: {}: {} extraordinary vertices or face centres keep Catmull-Clark \
             (boundary, crease or feature nearby)",
            input.name,
            surface.uncapped().len()
        ));
    }
    write_output(args, &out, fmt, &surface, &scheme, &input, &adjust_flags)?;
    if args.report {
        print_report(
            &out,
            &surface,
            &input.name,
            mixed.map(|_| adjust_flags.trim()),
        )?;
    }
    Ok(())
}

/// Writes `surface` to `out` in `fmt`: a tessellation (OBJ, PLY, STL, glTF), a picture
/// (PNG), or the patches' control points (JSON, IGES).
fn write_output(
    args: &G2Args,
    out: &Output,
    fmt: Format,
    surface: &G2Surface,
    scheme: &Options,
    input: &Input,
    adjust_flags: &str,
) -> Result<()> {
    let (name, mesh) = (input.name.as_str(), &input.obj.mesh);
    match fmt {
        Format::Png => {
            let mut opts = Render {
                geometry: Geometry::Limit { rate: args.rate },
                width: args.size.0,
                height: args.size.1,
                zoom: args.zoom,
                curvature_range: args.range,
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
            let g2: &dyn Surface = surface;
            let uncapped = Uncapped(surface);
            let drawn_surface = match (args.compare, surface.mixed().is_some()) {
                (false, _) => Some(g2),
                (true, true) => Some(&uncapped as &dyn Surface),
                (true, false) => None,
            };
            let drawn = render_surface(mesh, scheme, &opts, drawn_surface)
                .with_context(|| name.to_owned())?;
            out.write(|w| write_png(w, &drawn.image))?;
        }
        Format::Json => {
            let doc = patches_json(surface, mesh).with_context(|| name.to_owned())?;
            let text = doc.to_json();
            out.write(|w| writeln!(w, "{text}"))?;
        }
        Format::Iges => {
            let doc = patches_json(surface, mesh).with_context(|| name.to_owned())?;
            let name = args
                .output
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let text = to_iges(&doc, &name);
            out.write(|w| w.write_all(text.as_bytes()))?;
        }
        tessellation => {
            let format = tessellation
                .tessellation()
                .context("not a tessellation format")?;
            let triangles = format == TessellationFormat::Glb;
            let t =
                tessellate(surface, mesh, args.rate, triangles).with_context(|| name.to_owned())?;
            let comment = format!(
                "subsurf g2 --rate {}{} {}: {} caps",
                args.rate,
                adjust_flags,
                name,
                surface.caps().len()
            );
            let options = TessellationWriteOptions {
                comment: &comment,
                ..Default::default()
            };
            out.write(|mut w| write_tessellation(&mut w, format, &t, &options))?;
        }
    }
    Ok(())
}

/// Prints the continuity report of `surface` (to standard error when the surface goes to
/// standard output); `mixed`: the `--c` flags of a mixed surface.
fn print_report(out: &Output, surface: &G2Surface, name: &str, mixed: Option<&str>) -> Result<()> {
    let r = continuity_report(surface, 24).with_context(|| name.to_owned())?;
    let text = format!(
        "{}{}: {} caps, {} left with Catmull-Clark; 24 samples per boundary\n{r}",
        name,
        mixed.map_or(String::new(), |flags| {
            format!(" ({flags}; the Catmull-Clark rows are the mixed surface without caps)")
        }),
        surface.caps().len(),
        surface.uncapped().len()
    );
    if matches!(out, Output::Stdout) {
        crate::output::eprint_line(text.trim_end_matches('\n'));
    } else {
        crate::output::print(&text)?;
    }
    for u in surface.uncapped() {
        let what = match (u.vertex, u.face) {
            (Some(v), _) => format!("vertex {v}"),
            (None, Some(f)) => format!("centre of face {f}"),
            _ => "?".into(),
        };
        let line = format!("  {what} (valence {}): {}", u.valence, u.reason);
        if matches!(out, Output::Stdout) {
            crate::output::eprint_line(&line);
        } else {
            crate::output::print(&format!("{line}\n"))?;
        }
    }
    Ok(())
}

/// The surface without caps (`--compare` with `--c`: the mixed surface).
struct Uncapped<'a>(&'a G2Surface);

impl Surface for Uncapped<'_> {
    fn num_faces(&self) -> usize {
        self.0.num_faces()
    }

    fn num_subfaces(&self, f: usize) -> usize {
        self.0.num_subfaces(f)
    }

    fn has_surface(&self, f: usize) -> bool {
        self.0.has_surface(f)
    }

    fn evaluate(&self, p: SurfacePoint) -> Result<Derivatives, EvalError> {
        self.0.eval_uncapped(p)
    }
}

/// Refuses `--adjust-steps` whose refined mesh would not fit in the available memory
/// (the estimate of `subsurf subdivide`).
fn check_memory(mesh: &subsurf::mesh::PolyMesh, scheme: Options, steps: u32) -> Result<()> {
    let opts = SubdivideOptions {
        levels: steps,
        options: scheme,
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
