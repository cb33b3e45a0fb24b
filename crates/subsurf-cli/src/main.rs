//! `subsurf`: Catmull-Clark subdivision of OBJ meshes from the command line.
//!
//! This file holds the argument definitions, the dispatch to one module per subcommand and
//! the exit codes: 0 success, 1 bad input or any other failure, 2 usage error (clap's).
//!
//! Output goes through `output::print` and `output::eprint_line`, never `println!` and
//! friends, which panic when standard output or error is closed or full.
#![deny(clippy::print_stdout, clippy::print_stderr)]

mod cmd;
mod input;
mod json;
mod memory;
mod output;
mod paths;
mod progress;
mod signals;

use std::io;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand};
use subsurf::io::FileOptions;
use subsurf::mesh::{
    BoundaryInterpolation, CreaseMethod, FaceVaryingInterpolation, TriangleSubdivision,
};

/// mimalloc keeps freed memory for reuse in large regions backed by transparent huge pages:
/// refinement writes hundreds of MB of fresh buffers, and with the system allocator the
/// kernel's 4 KiB page faults cost as much as the work (see the `subsurf` crate docs).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const MAIN_EXAMPLES: &str = "\
Examples:
  subsurf subdivide model.obj -o smooth.obj -l 3
  subsurf info model.obj
  subsurf demo -o subsurf-demo

Run 'subsurf help <command>' for the options of each command.";

const SUBDIVIDE_EXAMPLES: &str = "\
Scheme options are read from the file's tags (t interpolateboundary, t creasemethod,
t smoothtriangles); the flags above override them when given.

Examples:
  subsurf subdivide cube.obj -o cube-l3.obj -l 3
  subsurf subdivide shape.obj -o shape-limit.obj --limit   (limit positions, normals, vt)
  subsurf subdivide grid.obj -o grid-l2.obj --boundary edge-and-corner
  subsurf subdivide big.obj -o big-l4.obj -l 4 --max-memory 8G
  cat cube.obj | subsurf subdivide - -o - -l 1 > cube-l1.obj
  subsurf subdivide knots.obj -o knots-l2.obj --scheme nurss   (knot intervals: t interval)";

const INFO_EXAMPLES: &str = "\
Examples:
  subsurf info model.obj
  subsurf info grid.obj --boundary none
  subsurf info model.obj --json > model-info.json";

const DEMO_EXAMPLES: &str = "\
Examples:
  subsurf demo                  (writes to ./subsurf-demo)
  subsurf demo -o /tmp/shapes";

/// Catmull-Clark subdivision surfaces, exactly as OpenSubdiv computes them.
#[derive(Debug, Parser)]
#[command(name = "subsurf", version, after_help = MAIN_EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Worker threads, for every command [default: one per core, or the environment's
    /// RAYON_NUM_THREADS]. At most 4 per core: more would only add memory and switching.
    #[arg(long, global = true, value_name = "N", value_parser = parse_threads)]
    threads: Option<usize>,
}

/// The most worker threads `--threads` starts: 4 per core that the system reports.
fn max_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get()) * 4
}

/// Parses `--threads N`: 1 up to [`max_threads`] (0: one per core).
fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of threads"))?;
    let max = max_threads();
    if n > max {
        return Err(format!(
            "{n} threads is more than 4 per core of this machine's {} (at most {max})",
            max / 4
        ));
    }
    Ok(n)
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Refine an OBJ mesh N levels with Catmull-Clark and write it as OBJ.
    #[command(after_help = SUBDIVIDE_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it; needs --scheme adjustable")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: every level]")))]
    Subdivide(SubdivideArgs),
    /// Print a summary of an OBJ mesh: counts, valences, boundaries, manifoldness, tags.
    #[command(after_help = INFO_EXAMPLES)]
    Info(InfoArgs),
    /// Write the bundled example meshes and their refinements to a directory.
    #[command(after_help = DEMO_EXAMPLES)]
    Demo(DemoArgs),
    /// Sample the exact limit surface on an N×N grid per quad face and per sub-face of other
    /// faces (osd-oracle limit layout, Bfr's parameterisation).
    #[command(after_help = LIMIT_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it: samples the mixed limit surface")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: 1]")))]
    Limit(LimitArgs),
    /// Sample the exact limit surface on a watertight grid; write OBJ, PLY, STL or binary glTF.
    #[command(after_help = TESSELLATE_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it: tessellates the mixed limit surface")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: 1]")))]
    Tessellate(TessellateArgs),
    /// Refine a base mesh once, then each pose (the base's vertices moved) with a re-posing
    /// plan; write each refined pose as OBJ.
    #[command(after_help = cmd::repose::REPOSE_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it; needs --scheme adjustable")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: every level]")))]
    Repose(cmd::repose::ReposeArgs),
    /// Time uniform refinement (topology, positions, texture coordinates; no output), like `osd-oracle bench`.
    #[command(after_help = BENCH_EXAMPLES)]
    Bench(BenchArgs),
    /// Draw the limit surface (or a refined mesh) to a PNG: shaded, zebra stripes, curvature.
    #[command(after_help = RENDER_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it: draws the mixed limit surface (--control-mesh then draws the c-refined mesh)")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: 1]")))]
    Render(RenderArgs),
    /// Read NURBS curves and surfaces (JSON or OBJ free-form): summary, conversion, samples.
    #[command(after_help = NURBS_EXAMPLES)]
    Nurbs(NurbsArgs),
    /// Build a mesh whose smooth (NURSS) limit surface passes through cubic NURBS curves.
    #[command(after_help = cmd::interpolate::INTERPOLATE_EXAMPLES)]
    Interpolate(cmd::interpolate::InterpolateArgs),
    /// Sample the sub-basis spline surface on a watertight grid; write OBJ, PLY or STL.
    #[command(after_help = cmd::spline::SPLINE_EXAMPLES)]
    Spline(cmd::spline::SplineArgs),
    /// Certify that the limit surface is regular (no vanishing normal, no fold) from the
    /// control net's difference cones (Wang et al. 2016); exit 3 when not certified.
    #[command(after_help = cmd::regularity::REGULARITY_EXAMPLES)]
    Regularity(cmd::regularity::RegularityArgs),
    /// Replace the surface at extraordinary vertices by G2 bi-septic caps (Tang et al. 2017); write a
    /// tessellation (OBJ) or the patches' control points (JSON), optionally a continuity report.
    #[command(after_help = cmd::g2::G2_EXAMPLES)]
    #[command(mut_arg("c", |a| a.help("Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller stays closer to the control mesh (0: the mesh itself), larger moves away from it: the G2 caps go on the mixed surface")), mut_arg("adjust_steps", |a| a.help("Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed subdivision) [default: 1]")))]
    G2(cmd::g2::G2Args),
    /// Blend N bicubic B-spline patches C2 with a NURSS surface (skirt removal).
    #[command(after_help = cmd::blend::BLEND_EXAMPLES)]
    Blend(cmd::blend::BlendArgs),
    /// Fill an N-sided hole bounded by cubic curves or patches (corner interpolating).
    #[command(after_help = cmd::fill::FILL_EXAMPLES)]
    Fill(cmd::fill::FillArgs),
}

const NURBS_EXAMPLES: &str = "\
Input is JSON (one document or an array, schema in docs/cli.md) or OBJ free-form geometry
(cstype [rat] bspline|bezier, deg, curv, surf, parm, end), told apart by the first character.
Without -o, prints one line per curve or surface. With -o, writes them as JSON (.json, or
'-' for standard output) or OBJ free-form (.obj); both read back exactly. --sample N writes
OBJ quad grids (surfaces) and polylines (curves) instead, one group per element, N
segments per knot span.

Examples:
  subsurf nurbs curves.obj
  subsurf nurbs curves.obj -o curves.json
  subsurf nurbs patches.json -o patches-sampled.obj --sample 16";

/// Arguments of `subsurf nurbs`.
#[derive(Debug, Args)]
pub struct NurbsArgs {
    /// Input file: JSON documents or OBJ free-form elements ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output file, .json or .obj ('-' writes JSON, or OBJ with --sample, to standard
    /// output); without it a summary is printed.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Write samples instead: polylines and quad grids with N segments per knot span.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10000))]
    pub sample: Option<u32>,
    /// Refuse to start sampling when the estimated memory exceeds this (suffixes K, M, G, T:
    /// powers of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
}

const LIMIT_EXAMPLES: &str = "\
One line per sample: 'face u v px py pz dux duy duz dvx dvy dvz', faces in order (holes have
none); when the mesh has texture coordinates (vt), each line ends with their limit 's t' (the
face-varying limit of OpenSubdiv's Bfr in the --fvar mode; not with --scheme nurss, which
notes it). A quad gets an N x N grid, u = i/(N-1) outer, v = j/(N-1) inner (u = v = 0.5 when N = 1),
as osd-oracle limit prints it. A face of n != 4 vertices (a triangle too) is sampled on each of
its n quad sub-faces in turn, the same N x N grid in the sub-face's own (s, t), and its rows
give (u, v) in OpenSubdiv Bfr's parameterisation of the face: sub-face k is the tile in column
k mod D and row floor(k / D) of a grid D = ceil(sqrt(n)) tiles wide, u = k mod D + s/2,
v = floor(k / D) + t/2 (s = t = 0 at vertex k, s toward vertex k+1, (s, t) = (1, 1) at the
face's centre), and du, dv are derivatives by that u, v (twice those by s, t), so that
Bfr::Surface::Evaluate at (u, v) gives the same row. At an extraordinary vertex (a face's
centre too) the derivatives are tangent directions (see the library docs of LimitSurface).
With --scheme loop (every face a triangle; another face is an error naming it) each triangle
gets the triangular grid u = i/(N-1) outer, v = j/(N-1) inner, i + j <= N-1 (the centroid when
N = 1), in OpenSubdiv's triangle parameterisation ((0,0) at its first vertex, u toward the
second, v toward the third), as osd-oracle limit --scheme loop prints it.
With --scheme bilinear the limit of bilinear subdivision is sampled in the layout above: the
bilinear patch of each quad, and of each sub-face of another face (its vertex, the midpoints
of its two edges there and its centre), as OpenSubdiv's Bfr evaluates it; creases, corners and
the boundary mode do not change it, and the texture coordinates are linear in every --fvar mode.
With knot interval or weight tags (or --scheme nurss) the non-uniform (NURSS) surface is
sampled; it is evaluated exactly, with derivatives, only on faces whose neighbourhood is a
regular grid of quads or has equal intervals (see the library docs of NurssSurface), and any
other face is an error naming it.

Examples:
  subsurf limit model.obj --grid 5 -o samples.tsv
  subsurf limit textured.obj --grid 3 --fvar corners-only -o uv-samples.tsv
  subsurf limit model.obj --grid 3 -o - | head
  subsurf limit model.obj --grid 5 -o tight.tsv --c 0.3
  subsurf limit scan.obj --scheme loop --grid 5 -o loop-samples.tsv
  subsurf limit cage.obj --scheme bilinear --grid 3 -o cage-samples.tsv";

/// Arguments of `subsurf limit`.
#[derive(Debug, Args)]
pub struct LimitArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Samples per side of each face.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub grid: u32,
    /// Output file of text rows, .txt, .tsv or .dat ('-' for standard output).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Surface to sample [default: nurss when the file has knot interval or weight tags,
    /// adjustable with --c, else catmull-clark].
    #[arg(long = "scheme", id = "scheme_kind", value_name = "SCHEME", value_enum)]
    pub scheme_kind: Option<SchemeKind>,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Face-varying (texture coordinate) interpolation of the 's t' columns: none,
    /// corners-only, corners-plus1, corners-plus2, boundaries or all (OpenSubdiv's
    /// FVarLinearInterpolation) [default: the file's t facevaryinginterpolateboundary tag,
    /// else all].
    #[arg(long, value_name = "MODE", value_parser = fvar_parser())]
    pub fvar: Option<FaceVaryingInterpolation>,
    /// Print no warnings or notes.
    #[arg(short, long)]
    pub quiet: bool,
}

const TESSELLATE_EXAMPLES: &str = "\
Each quad face becomes N x N quads sampled at u = i/N, v = j/N on the exact limit surface;
samples on shared edges and vertices are evaluated once and shared, so the output is
watertight. A non-quad face is sampled through its quad sub-faces at N/2 x N/2 (an odd N is
rounded up when the mesh has non-quad faces). With --scheme loop each triangle becomes the
N x N triangles of its grid u = i/N, v = j/N, i + j <= N. Holes produce no faces. The format follows
OUT's extension: .obj (positions and vn normals, full precision), .ply (binary, f64
positions and normals), .stl (binary, f32, triangles), .glb (binary glTF, f32 triangles
and normals, turned to glTF's +Y up from --up, Z by default). '-o -' writes OBJ to
standard output. When the mesh has texture coordinates (vt), the output has their exact
limit (OpenSubdiv Bfr's face-varying limit in the --fvar mode) at every corner: OBJ vt with
f v/vt/vn faces, PLY s t and glTF TEXCOORD_0 (a vertex on a UV seam is written once per
side); STL cannot store them (a note says so), nor does NURSS give them.

Examples:
  subsurf tessellate model.obj -o model-smooth.obj --rate 8
  subsurf tessellate model.obj -o model.ply --rate 16
  subsurf tessellate model.obj -o print.stl --rate 12 --triangles
  subsurf tessellate textured.obj -o textured.glb --rate 8 --fvar corners-only
  subsurf tessellate scan.obj -o scan-smooth.ply --rate 4 --scheme loop
  subsurf tessellate grid.obj -o - --rate 4 --boundary edge-and-corner > grid-limit.obj";

/// Arguments of `subsurf tessellate`.
#[derive(Debug, Args)]
pub struct TessellateArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output file, .obj, .ply, .stl or .glb ('-' writes OBJ to standard output); written only
    /// when everything succeeded.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Segments per base edge: each quad becomes N x N quads.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub rate: u32,
    /// Split every quad into two triangles (along its shorter diagonal).
    #[arg(long)]
    pub triangles: bool,
    /// With a .glb output: add the input mesh's edges as lines (a "control mesh" node).
    #[arg(long)]
    pub control_mesh: bool,
    /// With a .glb output: which axis of the input points up [default: z]. glTF is Y-up,
    /// so a Z-up mesh is turned a quarter turn about X ((x, y, z) -> (x, z, -y)); a Y-up
    /// mesh is written as it is.
    #[arg(long, value_name = "AXIS", value_parser = ["z", "y"])]
    pub up: Option<String>,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Surface to sample [default: nurss when the file has knot interval or weight tags,
    /// adjustable with --c, else catmull-clark]. NURSS is sampled through refinement: the
    /// rate is rounded up to a power of two and normals are those of the sampled mesh.
    #[arg(long = "scheme", id = "scheme_kind", value_name = "SCHEME", value_enum)]
    pub scheme_kind: Option<SchemeKind>,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Face-varying (texture coordinate) interpolation of the output's texture coordinates:
    /// none, corners-only, corners-plus1, corners-plus2, boundaries or all (OpenSubdiv's
    /// FVarLinearInterpolation) [default: the file's t facevaryinginterpolateboundary tag,
    /// else all].
    #[arg(long, value_name = "MODE", value_parser = fvar_parser())]
    pub fvar: Option<FaceVaryingInterpolation>,
    /// Print no warnings or notes.
    #[arg(short, long)]
    pub quiet: bool,
}

const RENDER_EXAMPLES: &str = "\
Draws with a built-in software rasteriser (deterministic: same input, same bytes). Without
--level the exact limit surface is drawn, sampled N x N per quad face (--limit-rate, default
16) with exact limit normals; --level L draws the control mesh refined L times instead.
Holes are not drawn. The camera orbits the centre of the bounding box (--view AZ,EL in
degrees; --up z: azimuth 0 looks along +Y; --up y: along -Z) and fits the bounding sphere.
--zebra shows reflection lines (broken stripes: a kink; kinked stripes: a curvature jump).
--curvature colours by the exact limit curvature (mean > 0 where convex), with a colour bar;
the range ignores outliers (98th percentile of |value|, capped near creases) unless --range
is given. Meshes of more than 16 000 faces get a lower default rate. --control-mesh draws
the input's edges on top: dark where in front of the surface, faint where hidden.
--scheme loop draws a triangle mesh's Loop limit surface (N x N triangles per triangle) or
its Loop levels, --scheme bilinear the bilinear one; --c C the shape-adjustable (mixed)
surface.
--texture checker maps a checkerboard through the texture coordinates (vt): on the limit
surface their exact limit in the --fvar mode, on a --level the refined ones; seams, stretching
and coordinates outside the unit square (tinted red) show.

Examples:
  subsurf render model.obj -o model.png
  subsurf render model.obj -o zebra.png --zebra --size 1200x900
  subsurf render model.obj -o mean.png --curvature mean --view 45,30
  subsurf render model.obj -o cage.png --level 2 --shade flat --control-mesh
  subsurf render model.obj -o patches.png --faces --up y
  subsurf render scan.obj -o scan-zebra.png --zebra --scheme loop
  subsurf render textured.obj -o uv.png --texture checker --squares 16 --fvar corners-only";

/// Arguments of `subsurf render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output PNG file ('-' writes the PNG to standard output); written only when
    /// everything succeeded.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Draw the control mesh refined L times (0: the input) instead of the limit surface.
    #[arg(long, value_name = "L", value_parser = clap::value_parser!(u32).range(0..=8))]
    pub level: Option<u32>,
    /// Samples per base edge of the limit surface [default: 16, lower for meshes of more
    /// than 16 000 faces].
    #[arg(long, value_name = "N", conflicts_with = "level", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub limit_rate: Option<u32>,
    /// Normals: smooth (interpolated) or flat (one per polygon).
    #[arg(long, value_name = "MODE", default_value = "smooth", value_parser = ["smooth", "flat"])]
    pub shade: String,
    /// Reflection lines (zebra stripes) instead of plain shading.
    #[arg(long, conflicts_with_all = ["curvature", "faces"])]
    pub zebra: bool,
    /// Colour by the exact limit curvature: gauss, mean or max (largest |principal|).
    #[arg(long, value_name = "KIND", conflicts_with_all = ["faces", "level"], value_parser = ["gauss", "mean", "max"])]
    pub curvature: Option<String>,
    /// Fixed curvature colour range instead of the automatic one.
    #[arg(long, value_name = "MIN,MAX", requires = "curvature", allow_hyphen_values = true, value_parser = cmd::render::parse_pair)]
    pub range: Option<(f64, f64)>,
    /// Colour base faces alternately (neighbours differ) to show the patches.
    #[arg(long)]
    pub faces: bool,
    /// Map a texture through the mesh's texture coordinates (vt): checker, a checkerboard
    /// of --squares squares per side of the unit square (tinted red outside it).
    #[arg(long, value_name = "KIND", value_parser = ["checker"], conflicts_with_all = ["zebra", "curvature", "faces"])]
    pub texture: Option<String>,
    /// Squares per side of the --texture checker.
    #[arg(long, value_name = "N", default_value_t = 8, requires = "texture", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub squares: u32,
    /// Face-varying interpolation of the texture coordinates: none, corners-only,
    /// corners-plus1, corners-plus2, boundaries or all (OpenSubdiv's FVarLinearInterpolation)
    /// [default: the file's t facevaryinginterpolateboundary tag, else all].
    #[arg(long, value_name = "MODE", requires = "texture", value_parser = fvar_parser())]
    pub fvar: Option<FaceVaryingInterpolation>,
    /// Draw the input control mesh's edges on top.
    #[arg(long)]
    pub control_mesh: bool,
    /// Camera azimuth and elevation in degrees.
    #[arg(long, value_name = "AZ,EL", default_value = "30,20", allow_hyphen_values = true, value_parser = cmd::render::parse_pair)]
    pub view: (f64, f64),
    /// Which axis points up.
    #[arg(long, value_name = "AXIS", default_value = "z", value_parser = ["z", "y"])]
    pub up: String,
    /// Magnify the fitted view F times around the picture's centre (e.g. to look at a
    /// vertex placed there with --view).
    #[arg(long, value_name = "F", default_value_t = 1.0, value_parser = cmd::render::parse_zoom)]
    pub zoom: f64,
    /// Picture size in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", value_parser = cmd::render::parse_size)]
    pub size: (u32, u32),
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Surface to draw: catmull-clark, adjustable (with --c, the default with --c), loop (a
    /// mesh of triangles) or bilinear (the control mesh itself, n-gons split at their
    /// centroids) [default: catmull-clark]; --level draws its refined levels.
    #[arg(long = "scheme", id = "scheme_kind", value_name = "SCHEME", value_enum)]
    pub scheme_kind: Option<SchemeKind>,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Print no warnings or notes.
    #[arg(short, long)]
    pub quiet: bool,
}

const BENCH_EXAMPLES: &str = "\
Prints 'median_s=<seconds> min_s=<seconds>' over the repetitions, as osd-oracle bench does.
Face-varying channels (texture coordinates, vt) are refined with the positions (as
osd-oracle bench --fvar does); a mesh that has them is timed again without them, and the line
ends with 'channels=<n> vertices_s=<seconds> fvar_pct=<their share, % of vertices_s>'.

Examples:
  subsurf bench catmark_bishop.obj -l 5 --reps 7
  subsurf bench big.obj -l 3 --threads 1";

/// Arguments of `subsurf bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Number of refinement levels.
    #[arg(short, long, value_name = "N", default_value_t = 5)]
    pub levels: u32,
    /// Repetitions (the median and the minimum are printed).
    #[arg(long, value_name = "R", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    pub reps: u32,
    /// Time limit evaluation instead: build the exact limit surface and evaluate an N×N
    /// grid on every quad face, or with `--scheme loop` a grid of N points a side on every
    /// triangle (as `osd-oracle benchlimit IN N REPS`). Prints the first build plus
    /// evaluation (`cold_s`) and the repetitions on the built surface (`median_s`,
    /// `min_s`).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub limit_grid: Option<u32>,
    /// Time re-posing instead: build a refinement plan once (its build time is printed,
    /// not timed) and time applying it to the base positions.
    #[arg(long, conflicts_with = "limit_grid")]
    pub replay: bool,
    /// Refuse to start when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Subdivision scheme: catmull-clark, loop or bilinear (OpenSubdiv's three, as
    /// `osd-oracle bench --scheme`; refinement and --replay).
    #[arg(
        long = "scheme",
        id = "scheme_kind",
        value_name = "SCHEME",
        value_enum,
        default_value = "catmull-clark"
    )]
    pub scheme_kind: SchemeKind,
    /// Print no warnings.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Arguments of `subsurf subdivide`.
#[derive(Debug, Args)]
pub struct SubdivideArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Output OBJ file ('-' writes to standard output); written only when everything succeeded.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Number of refinement levels (0 copies the mesh).
    #[arg(short, long, value_name = "N", default_value_t = 2)]
    pub levels: u32,
    #[command(flatten)]
    pub scheme: SchemeArgs,
    /// Subdivision scheme [default: nurss when the file has knot interval or weight tags
    /// (t interval, t sideinterval, t weight), else catmull-clark].
    #[arg(long = "scheme", id = "scheme_kind", value_name = "SCHEME", value_enum)]
    pub scheme_kind: Option<SchemeKind>,
    #[command(flatten)]
    pub adjust: AdjustArgs,
    /// Face-varying (texture coordinate) interpolation: none, corners-only, corners-plus1,
    /// corners-plus2, boundaries or all (OpenSubdiv's FVarLinearInterpolation) [default:
    /// the file's t facevaryinginterpolateboundary tag, else all].
    #[arg(long, value_name = "MODE", value_parser = fvar_parser())]
    pub fvar: Option<FaceVaryingInterpolation>,
    /// Move the last level's vertices to the limit surface and write limit normals; texture
    /// coordinates (vt) move to their limit too (OpenSubdiv's LimitFaceVarying).
    #[arg(long)]
    pub limit: bool,
    /// Crease every interior edge whose faces' normals differ by more than DEG degrees
    /// (0..=180; 90 on a cube's edges). The file's own crease tags win on the same edge.
    #[arg(
        long,
        value_name = "DEG",
        allow_negative_numbers = true,
        value_parser = cmd::subdivide::parse_crease_angle
    )]
    pub crease_angle: Option<f64>,
    /// Sharpness of the --crease-angle creases (10 or more: infinitely sharp).
    #[arg(
        long,
        value_name = "S",
        default_value_t = subsurf::mesh::SHARPNESS_INFINITE,
        requires = "crease_angle",
        allow_negative_numbers = true,
        value_parser = cmd::subdivide::parse_sharpness
    )]
    pub sharpness: f32,
    /// Keep hole faces in the output (tagged as holes) instead of leaving them out.
    #[arg(long)]
    pub keep_holes: bool,
    /// Refuse to refine when the estimated memory exceeds this (suffixes K, M, G, T: powers
    /// of 1024) [default: the memory the system reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Reject faces that repeat a vertex and non-manifold or inconsistently oriented
    /// topology (by default they are refined as OpenSubdiv refines them, with a warning).
    #[arg(long)]
    pub strict: bool,
    /// Print no warnings and no progress bar.
    #[arg(short, long)]
    pub quiet: bool,
}

/// The subdivision scheme of `subsurf subdivide`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SchemeKind {
    /// Catmull-Clark, exactly as OpenSubdiv.
    CatmullClark,
    /// Shape-adjustable Catmull-Clark with parameter --c (0.5 is Catmull-Clark).
    Adjustable,
    /// Non-uniform Catmull-Clark (NURSS): knot intervals on edges and rational weights from
    /// the file's tags (untagged edges: interval 1; all equal: Catmull-Clark).
    Nurss,
    /// Loop, for triangle meshes, exactly as OpenSubdiv (refinement, --limit, repose, and
    /// its exact limit with limit, tessellate and render).
    Loop,
    /// Bilinear, exactly as OpenSubdiv: the control mesh split, not smoothed (refinement,
    /// --limit, repose, and its exact limit with limit, tessellate and render).
    Bilinear,
}

/// Flags of the shape-adjustable scheme.
#[derive(Debug, Args)]
pub struct AdjustArgs {
    /// Shape parameter of the adjustable scheme, in [0, 1]: 0.5 is Catmull-Clark, smaller
    /// stays closer to the control mesh (0: the mesh itself), larger moves away from it.
    #[arg(long = "c", value_name = "C", allow_negative_numbers = true, value_parser = cmd::adjustable::parse_c)]
    pub c: Option<f64>,
    /// Use the adjustable scheme for the first K steps only, then Catmull-Clark (mixed
    /// subdivision).
    #[arg(long, value_name = "K", requires = "c")]
    pub adjust_steps: Option<u32>,
}

/// Scheme flags; each overrides the file's tag only when given.
#[derive(Debug, Args)]
pub struct SchemeArgs {
    /// Boundary interpolation [default: the file's tag, else edge-only].
    #[arg(long, value_name = "MODE", value_parser = boundary_parser())]
    pub boundary: Option<BoundaryInterpolation>,
    /// How semi-sharp creases decay [default: the file's tag, else uniform].
    #[arg(long, value_name = "METHOD", value_parser = crease_method_parser())]
    pub crease_method: Option<CreaseMethod>,
    /// Use the smooth rule for edges next to triangles (OpenSubdiv's TRI_SUB_SMOOTH).
    #[arg(long)]
    pub smooth_triangles: bool,
}

impl SchemeArgs {
    /// The file's options with the flags that were given on top.
    pub fn over(&self, file: FileOptions) -> FileOptions {
        FileOptions {
            boundary: self.boundary.or(file.boundary),
            crease_method: self.crease_method.or(file.crease_method),
            triangles: self
                .smooth_triangles
                .then_some(TriangleSubdivision::Smooth)
                .or(file.triangles),
            face_varying: file.face_varying,
        }
    }
}

/// Arguments of `subsurf info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Input mesh: OBJ, PLY or glTF (.gltf, .glb) ('-' reads standard input).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Boundary interpolation used to classify the topology [default: the file's tag, else
    /// edge-only].
    #[arg(long, value_name = "MODE", value_parser = boundary_parser())]
    pub boundary: Option<BoundaryInterpolation>,
    /// Print a JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Fail (exit 1) on faces that repeat a vertex and on non-manifold or inconsistently
    /// oriented topology.
    #[arg(long)]
    pub strict: bool,
    /// Refuse an input whose bytes and the mesh read from them would need more memory
    /// than this (suffixes K, M, G, T: powers of 1024) [default: the memory the system
    /// reports as available].
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
}

/// Arguments of `subsurf demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Directory to write into (created if missing).
    #[arg(short, long, value_name = "DIR", default_value = "subsurf-demo")]
    pub output: PathBuf,
}

/// `edge` and `corner` are accepted too: the names `osd-oracle` and OpenSubdiv's
/// `VTX_BOUNDARY_EDGE_ONLY` / `VTX_BOUNDARY_EDGE_AND_CORNER` use.
fn boundary_parser() -> impl TypedValueParser<Value = BoundaryInterpolation> {
    PossibleValuesParser::new([
        PossibleValue::new("edge-only").alias("edge"),
        PossibleValue::new("edge-and-corner").alias("corner"),
        PossibleValue::new("none"),
    ])
    .try_map(|s| s.parse::<BoundaryInterpolation>())
}

fn fvar_parser() -> impl TypedValueParser<Value = FaceVaryingInterpolation> {
    PossibleValuesParser::new([
        "none",
        "corners-only",
        "corners-plus1",
        "corners-plus2",
        "boundaries",
        "all",
    ])
    .try_map(|s| s.parse::<FaceVaryingInterpolation>())
}

fn crease_method_parser() -> impl TypedValueParser<Value = CreaseMethod> {
    PossibleValuesParser::new(["uniform", "chaikin"]).try_map(|s| s.parse::<CreaseMethod>())
}

/// Parses a byte count such as `1000000`, `512K`, `1.5G` or `2GiB` (binary multiples).
fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let digits_end = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(digits_end);
    let shift = match unit.trim().to_ascii_uppercase().as_str() {
        "" | "B" => 0,
        "K" | "KB" | "KIB" => 10,
        "M" | "MB" | "MIB" => 20,
        "G" | "GB" | "GIB" => 30,
        "T" | "TB" | "TIB" => 40,
        _ => {
            return Err(format!(
                "'{s}' is not a size (expected e.g. 500M, 8G or 1073741824)"
            ))
        }
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("'{s}' is not a size (expected e.g. 500M, 8G or 1073741824)"))?;
    let bytes = (value * (1u64 << shift) as f64).round();
    if !bytes.is_finite() || bytes >= u64::MAX as f64 {
        return Err(format!("'{s}' is too large"));
    }
    if bytes < 1.0 {
        return Err(format!("'{s}': a memory limit must be at least 1 byte"));
    }
    Ok(bytes as u64)
}

fn main() -> ExitCode {
    memory::allocator_at_start();
    // Usage errors exit with 2 here; --help and --version with 0.
    let cli = Cli::parse();
    if let Err(e) = paths::check(&cli.command) {
        output::eprint_line(&format!("error: {e}"));
        return ExitCode::from(2);
    }
    signals::clean_up_on_signals();
    let threads = cli.threads.unwrap_or(0);
    // `bench` times its own pool of exactly these threads; every other command runs on
    // rayon's global pool.
    if !matches!(cli.command, Command::Bench(_)) && threads > 0 {
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
        {
            crate::output::eprint_line(&format!(
                "error: cannot start {threads} worker threads: {e}"
            ));
            return ExitCode::FAILURE;
        }
    }
    let result = match &cli.command {
        Command::Subdivide(args) => cmd::subdivide::run(args),
        Command::Info(args) => cmd::info::run(args),
        Command::Demo(args) => cmd::demo::run(args),
        Command::Repose(args) => cmd::repose::run(args),
        Command::Bench(args) => cmd::bench::run(args, threads),
        Command::Limit(args) => cmd::limit::run(args),
        Command::Tessellate(args) => cmd::tessellate::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Nurbs(args) => cmd::nurbs::run(args),
        Command::Interpolate(args) => cmd::interpolate::run(args),
        Command::Spline(args) => cmd::spline::run(args),
        Command::Regularity(args) => cmd::regularity::run(args),
        Command::G2(args) => cmd::g2::run(args),
        Command::Blend(args) => cmd::blend::run(args),
        Command::Fill(args) => cmd::fill::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // `subsurf ... -o - | head`: the reader went away; that is not our failure.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        // The report was printed; the net is not certified.
        Err(e) if e.is::<cmd::regularity::NotCertified>() => ExitCode::from(3),
        Err(e) => {
            output::remove_created_dirs();
            crate::output::eprint_line(&format!("error: {e:#}"));
            ExitCode::FAILURE
        }
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<io::Error>()
            .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn byte_sizes() {
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert_eq!(parse_bytes("512K"), Ok(512 << 10));
        assert_eq!(parse_bytes("8g"), Ok(8 << 30));
        assert_eq!(parse_bytes("1.5G"), Ok(3 << 29));
        assert_eq!(parse_bytes("2GiB"), Ok(2 << 30));
        assert_eq!(parse_bytes("3 M"), Ok(3 << 20));
        assert!(parse_bytes("").is_err());
        assert!(parse_bytes("G").is_err());
        assert!(parse_bytes("12X").is_err());
        assert!(parse_bytes("-1").is_err());
        assert!(parse_bytes("1.2.3").is_err());
        assert!(parse_bytes("99999999999T").is_err());
        assert!(parse_bytes("0").is_err());
        assert!(parse_bytes("0.1").is_err());
    }

    #[test]
    fn flags_override_file_tags_only_when_given() {
        let file = FileOptions {
            boundary: Some(BoundaryInterpolation::None),
            crease_method: Some(CreaseMethod::Chaikin),
            triangles: Some(TriangleSubdivision::Smooth),
            face_varying: None,
        };
        let none = SchemeArgs {
            boundary: None,
            crease_method: None,
            smooth_triangles: false,
        };
        assert_eq!(none.over(file), file);
        let all = SchemeArgs {
            boundary: Some(BoundaryInterpolation::EdgeOnly),
            crease_method: Some(CreaseMethod::Uniform),
            smooth_triangles: true,
        };
        let got = all.over(FileOptions::default());
        assert_eq!(got.boundary, Some(BoundaryInterpolation::EdgeOnly));
        assert_eq!(got.crease_method, Some(CreaseMethod::Uniform));
        assert_eq!(got.triangles, Some(TriangleSubdivision::Smooth));
    }

    #[test]
    fn parses_subdivide_flags() {
        let cli = Cli::try_parse_from([
            "subsurf",
            "subdivide",
            "-",
            "-o",
            "-",
            "-l",
            "3",
            "--boundary",
            "none",
            "--crease-method",
            "chaikin",
            "--max-memory",
            "1G",
            "--limit",
            "-q",
        ])
        .expect("valid command line");
        let Command::Subdivide(a) = cli.command else {
            panic!("not subdivide")
        };
        assert_eq!(a.levels, 3);
        assert_eq!(a.scheme.boundary, Some(BoundaryInterpolation::None));
        assert_eq!(a.scheme.crease_method, Some(CreaseMethod::Chaikin));
        assert_eq!(a.max_memory, Some(1 << 30));
        assert!(a.limit && a.quiet && !a.keep_holes && !a.scheme.smooth_triangles);
        let cli = Cli::try_parse_from(["subsurf", "subdivide", "a.obj", "-o", "b.obj"])
            .expect("valid command line");
        let Command::Subdivide(a) = cli.command else {
            panic!("not subdivide")
        };
        assert_eq!(a.levels, 2);
        assert_eq!(a.scheme.boundary, None);
    }
}
