//! `subsurf regularity`: certify that the Catmull-Clark limit surface of a quad net is
//! regular ([Wang et al. 2016]), compare with dense samples of the exact limit surface, and print a
//! summary or JSON; optionally draw the net with its u- and v-difference fans.
//!
//! Exit status: 0 when every face is certified, 3 when not, 1 on bad input.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use subsurf::mesh::Options;
use subsurf::regularity::{
    check_regularity_with, plot_image, plot_svg, Certificate, Class, ConeTest, Dimension, Mode,
    RegularityOptions, RegularityReport, Sign, PLOT_HEIGHT, PLOT_WIDTH,
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
        format!("{}\n", json(&input.name, &report, mode))
    } else {
        summary(&input.name, &report, mode)
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
    if report.certified(mode) && report.counts(mode).contradictions == 0 {
        Ok(())
    } else {
        Err(NotCertified.into())
    }
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Global => "global",
        Mode::Local => "local",
    }
}

fn class_name(c: Class) -> &'static str {
    match c {
        Class::Certified => "certified",
        Class::RegularNotCertified => "regular-not-certified",
        Class::NotRegular => "not-regular",
        Class::Unsampled => "unsampled",
        Class::Contradiction => "contradiction",
    }
}

fn short(c: &Certificate) -> &'static str {
    match c {
        Certificate::Certified(_) => "certified",
        Certificate::Refused(_) => "refused",
        Certificate::NotApplicable(_) => "not-applicable",
    }
}

fn reason(c: &Certificate) -> Json {
    match c {
        Certificate::Certified(_) => Json::Null,
        Certificate::Refused(r) => Json::str(r.to_string()),
        Certificate::NotApplicable(i) => Json::str(i.to_string()),
    }
}

fn dimension_name(r: &RegularityReport) -> &'static str {
    match r.dimension {
        Dimension::Planar => "planar",
        Dimension::Spatial => "spatial",
    }
}

/// The human-readable report.
/// The text report of `subsurf regularity` on the net `name`: the net, both certificates'
/// verdicts, the global cones, the counts of `mode`'s certificate and of the samples, the
/// faces that fail, and the verdict.
fn summary(name: &str, r: &RegularityReport, mode: Mode) -> String {
    let mut s = String::new();
    let c = r.counts(mode);
    let orient = match (r.dimension, r.orientation) {
        (Dimension::Planar, Sign::Negative) => ", clockwise",
        (Dimension::Planar, _) => ", counter-clockwise",
        _ => "",
    };
    let _ = writeln!(
        s,
        "{name}: {} net{orient}, {} faces",
        dimension_name(r),
        r.faces.len()
    );
    let yes = |b: bool| if b { "certified" } else { "not certified" };
    let _ = writeln!(
        s,
        "global certificate (one cone pair per component): {}; local certificate (per face): {}",
        yes(r.certified(Mode::Global)),
        yes(r.certified(Mode::Local))
    );
    global_cones(&mut s, r);
    let _ = writeln!(
        s,
        "{} certificate: {} certified, {} refused, {} not applicable",
        mode_name(mode),
        c.certified,
        c.refused,
        c.not_applicable
    );
    if r.samples > 0 {
        let _ = writeln!(
            s,
            "limit surface sampled {n}x{n} per face: {} certified, {} regular but not certified, {} not regular",
            c.certified - c.contradictions,
            c.regular_not_certified,
            c.not_regular,
            n = r.samples
        );
        if c.contradictions > 0 {
            let _ = writeln!(
                s,
                "WARNING: {} certified faces have a sample at the singularity tolerance",
                c.contradictions
            );
        }
    }
    let _ = writeln!(
        s,
        "local certificate succeeds where the global one fails: {} faces",
        r.local_only()
    );
    failing_faces(&mut s, r, mode);
    let _ = writeln!(
        s,
        "verdict ({} certificate): {}",
        mode_name(mode),
        if r.certified(mode) && c.contradictions == 0 {
            "the limit surface is regular"
        } else {
            "not certified"
        }
    );
    s
}

/// The global cones' lines of the report: one per component with its difference counts
/// and whether its cones are disjoint (or why there are none).
fn global_cones(s: &mut String, r: &RegularityReport) {
    match &r.frames {
        Err(e) => {
            let _ = writeln!(s, "global cones: none ({e})");
        }
        Ok(_) => {
            for (i, comp) in r.components.iter().enumerate() {
                let verdict = match comp.test {
                    ConeTest::Disjoint(_) => "disjoint".to_owned(),
                    ConeTest::Meet(o) => o.to_string(),
                };
                let _ = writeln!(
                    s,
                    "global cones, component {i}: {} u-differences, {} v-differences: {verdict}",
                    comp.u.len(),
                    comp.v.len()
                );
            }
        }
    }
}

/// The report's lines on the faces that `mode`'s certificate fails or that a sample
/// contradicts: the first 20, each with its certificate and its worst sample.
fn failing_faces(s: &mut String, r: &RegularityReport, mode: Mode) {
    let bad: Vec<usize> = (0..r.faces.len())
        .filter(|&f| {
            !r.certificate(f, mode).is_certified()
                || matches!(r.class(f, mode), Class::Contradiction)
        })
        .collect();
    const SHOWN: usize = 20;
    for &f in bad.iter().take(SHOWN) {
        let mut line = format!("  face {f}: {}", r.certificate(f, mode));
        if let Some(sm) = r.faces[f].sampled {
            let w = sm.worst();
            let what = if sm.is_regular() {
                "sampled regular, least"
            } else {
                "sampled NOT regular"
            };
            let _ = write!(
                line,
                "; {what}: sine {:.3e} at (u, v) = ({}, {})",
                w.value, w.u, w.v
            );
        }
        let _ = writeln!(s, "{line}");
    }
    if bad.len() > SHOWN {
        let _ = writeln!(s, "  … and {} more faces", bad.len() - SHOWN);
    }
}

/// The JSON report (fields documented in `docs/regularity.md`).
fn json(name: &str, r: &RegularityReport, mode: Mode) -> Json {
    let c = r.counts(mode);
    let components = r
        .components
        .iter()
        .map(|comp| {
            Json::obj([
                ("u_differences", Json::count(comp.u.len())),
                ("v_differences", Json::count(comp.v.len())),
                (
                    "disjoint",
                    Json::Bool(matches!(comp.test, ConeTest::Disjoint(_))),
                ),
                (
                    "reason",
                    match comp.test {
                        ConeTest::Disjoint(_) => Json::Null,
                        ConeTest::Meet(o) => Json::str(o.to_string()),
                    },
                ),
            ])
        })
        .collect();
    let faces = r
        .faces
        .iter()
        .enumerate()
        .map(|(f, fr)| {
            let worst = fr.sampled.map_or(Json::Null, |sm| {
                let w = sm.worst();
                Json::obj([
                    ("u", Json::Num(w.u)),
                    ("v", Json::Num(w.v)),
                    ("value", Json::Num(w.value)),
                ])
            });
            Json::obj([
                ("face", Json::count(f)),
                ("local", Json::str(short(&fr.local))),
                ("local_reason", reason(&fr.local)),
                ("global", Json::str(short(&fr.global))),
                ("global_reason", reason(&fr.global)),
                ("class", Json::str(class_name(r.class(f, mode)))),
                ("worst_sample", worst),
            ])
        })
        .collect();
    Json::obj([
        ("file", Json::str(name)),
        ("dimension", Json::str(dimension_name(r))),
        (
            "orientation",
            match r.dimension {
                Dimension::Planar => Json::Int(if r.orientation == Sign::Negative {
                    -1
                } else {
                    1
                }),
                Dimension::Spatial => Json::Null,
            },
        ),
        ("mode", Json::str(mode_name(mode))),
        (
            "certified",
            Json::Bool(r.certified(mode) && c.contradictions == 0),
        ),
        ("global_certified", Json::Bool(r.certified(Mode::Global))),
        ("local_certified", Json::Bool(r.certified(Mode::Local))),
        ("local_only_faces", Json::count(r.local_only())),
        ("samples", Json::count(r.samples)),
        (
            "counts",
            Json::obj([
                ("faces", Json::count(r.faces.len())),
                ("certified", Json::count(c.certified)),
                ("refused", Json::count(c.refused)),
                ("not_applicable", Json::count(c.not_applicable)),
                (
                    "regular_not_certified",
                    Json::count(c.regular_not_certified),
                ),
                ("not_regular", Json::count(c.not_regular)),
                ("contradictions", Json::count(c.contradictions)),
            ]),
        ),
        (
            "labelling",
            match &r.frames {
                Ok(_) => Json::Null,
                Err(e) => Json::str(e.to_string()),
            },
        ),
        ("components", Json::Arr(components)),
        ("faces", Json::Arr(faces)),
    ])
}
