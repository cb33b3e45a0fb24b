//! `subsurf regularity`: certify that the Catmull-Clark limit surface of a quad net is
//! regular ([Wang et al. 2016]), compare with dense samples of the exact limit surface, and print a
//! summary or JSON; optionally draw the net with its u- and v-difference fans.
//!
//! Exit status: 0 when every face is certified, 3 when not, 1 on bad input.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use subsurf::mesh::Options;
use subsurf::regularity::{
    check_regularity_with, plot_image, plot_svg, Dimension, Mode, RegularityOptions, PLOT_HEIGHT,
    PLOT_WIDTH,
};

use crate::input::Input;
use crate::json::Json;
use crate::output::Output;
use crate::SchemeArgs;

/// Help text after the options.
pub const REGULARITY_EXAMPLES: &str = "\
Checks the sufficient condition of Wang, Lin, Wang and Lu ([Wang et al. 2016]) for nets whose interior
vertices have valence 4: the cone of the u-differences and the cone of the v-differences of
the control net meet only at the origin (and not along opposite rays). Global: one cone pair
per connected component (the paper's Theorem 3); --local: each face's own 4x4 patch
neighbourhood (certifies far more nets). A net is planar when every z is 0 (or with
--planar: x, y only): then the Jacobian must keep the net's orientation (no fold);
otherwise the normal must not vanish. Faces at interior extraordinary vertices and at
irregular boundary vertices are 'not applicable'; tag corners with edge-and-corner.
The limit surface is sampled N x N per face (--sample, 0: off) for the ground truth.
Exit status: 0 certified, 3 not certified, 1 bad input, 2 usage error.

Examples:
  subsurf regularity part.obj
  subsurf regularity part.obj --local --plot part-fans.svg
  subsurf regularity wing.obj --local --sample 17 --json > wing-regularity.json";

/// Arguments of `subsurf regularity`.
#[derive(Debug, clap::Args)]
pub struct RegularityArgs {
    /// Input OBJ file ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Decide by each face's patch neighbourhood instead of one cone pair per component.
    #[arg(long)]
    pub local: bool,
    /// Samples per side of each face for the ground truth (0: no sampling).
    #[arg(long, value_name = "N", default_value_t = 9, value_parser = parse_samples)]
    pub sample: u32,
    /// Print a JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Draw the net with its u (blue) and v (red) difference fans, faces tinted by class.
    #[arg(long, value_name = "OUT.svg|OUT.png", value_parser = parse_plot)]
    pub plot: Option<PathBuf>,
    /// Treat the net as planar (its x, y coordinates) even where z is not 0.
    #[arg(long)]
    pub planar: bool,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = crate::parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Peak bytes per face of the certificate and its report, the input included and the
/// limit surface aside (measured without sampling on planar and closed quad nets of 90 000
/// and 160 000 faces: 518–560).
const BYTES_PER_FACE: u64 = 768;

/// Peak bytes per face of the net of a `--plot` (SVG text or the PNG's scene; the PNG's
/// pixels are charged apart; measured on 90 000 faces: 680 for SVG, 60 for PNG).
const PLOT_BYTES_PER_FACE: u64 = 1024;

/// The memory of the job besides the limit surface: the report per face and the plot,
/// upper bounds of the measured peaks (RELIABILITY.md).
fn reserved_memory(mesh: &subsurf::mesh::PolyMesh, plot: bool) -> u64 {
    let faces = mesh.num_faces() as u64;
    let per_face = BYTES_PER_FACE + if plot { PLOT_BYTES_PER_FACE } else { 0 };
    let picture = if plot {
        u64::from(PLOT_WIDTH) * u64::from(PLOT_HEIGHT) * 16
    } else {
        0
    };
    faces.saturating_mul(per_face).saturating_add(picture)
}

/// The error that makes `subsurf regularity` exit with status 3: the report was printed,
/// and the net is not certified.
#[derive(Debug)]
pub struct NotCertified;

impl std::fmt::Display for NotCertified {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("not certified regular")
    }
}

impl std::error::Error for NotCertified {}

/// Parses `--sample N`: 0 (no sampling) or at least 2.
pub fn parse_samples(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(n) if n == 0 || (2..=1024).contains(&n) => Ok(n),
        _ => Err(format!("'{s}' is not a sample count (0, or 2 to 1024)")),
    }
}

/// Parses `--plot OUT`: a path ending in `.svg` or `.png`.
pub fn parse_plot(s: &str) -> Result<PathBuf, String> {
    let ext = Path::new(s)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("svg" | "png") => Ok(PathBuf::from(s)),
        _ => Err(format!("'{s}': the plot is written as .svg or .png")),
    }
}

/// Runs `subsurf regularity`.
pub fn run(args: &RegularityArgs) -> Result<()> {
    let plot_out = args.plot.as_ref().map(|p| Output::new(p));
    if let Some(o) = &plot_out {
        o.check()?;
    }
    let input = Input::read_surface(&args.input, args.max_memory)?;
    for w in input.warnings() {
        crate::output::eprint_line(&format!("warning: {w}"));
    }
    let scheme = args
        .scheme
        .over(input.obj.options)
        .resolve(Options::default());
    let options = RegularityOptions {
        scheme,
        dimension: args.planar.then_some(Dimension::Planar),
        samples: args.sample as usize,
    };
    let mesh = &input.obj.mesh;
    let reserved = reserved_memory(mesh, args.plot.is_some());
    let what = if args.sample > 0 {
        format!("sampling {n}x{n} per face", n = args.sample)
    } else {
        "certifying".to_owned()
    };
    let surface = if args.sample > 0 {
        // Only quads are sampled (`sample_faces`): the surface of other faces is not built.
        let guard = crate::memory::SurfaceGuard {
            name: &input.name,
            what: what.clone(),
            max: args.max_memory,
            hint: "use a lower --sample",
            quads_only: true,
        };
        Some(guard.limit_surface(mesh, scheme, args.sample - 1, reserved)?)
    } else {
        let hint = if args.plot.is_some() {
            "leave out --plot"
        } else {
            "the net is too large"
        };
        crate::memory::check(&input.name, &what, reserved, args.max_memory, hint)?;
        None
    };
    let report = check_regularity_with(mesh, &options, surface.as_ref())
        .with_context(|| input.name.clone())?;
    let mode = if args.local {
        Mode::Local
    } else {
        Mode::Global
    };
    let text = if args.json {
        let json = Json::parse(&report.to_json(Some(&input.name), mode))
            .map_err(|e| anyhow::anyhow!("the report's JSON: {e}"))?;
        format!("{json}\n")
    } else {
        report.summary(&input.name, mode)
    };
    Output::new(Path::new("-")).write(|w| w.write_all(text.as_bytes()))?;
    if let (Some(out), Some(path)) = (&plot_out, &args.plot) {
        let png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if png {
            let img = plot_image(mesh, &report, mode);
            out.write(|w| subsurf::render::write_png(w, &img))?;
        } else {
            let svg = plot_svg(mesh, &report, mode);
            out.write(|w| w.write_all(svg.as_bytes()))?;
        }
    }
    if report.regular(mode) {
        Ok(())
    } else {
        Err(NotCertified.into())
    }
}
