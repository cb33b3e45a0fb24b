//! `subsurf demo`: a gallery of every method of the project on the bundled examples.
//!
//! Three kinds of input are bundled (from `examples/` at the repository root):
//! - control meshes ([`EXAMPLES`], `examples/meshes/`): each goes through every entry of
//!   [`METHODS`] that applies to it (Catmull-Clark, its exact limit and pictures, the
//!   shape-adjustable scheme, non-uniform Catmull-Clark for meshes with knot intervals, G2
//!   caps where there are interior extraordinary vertices, the sub-basis spline on closed
//!   quad meshes, the regularity certificate on planar nets);
//! - cubic curves ([`CURVES`], `examples/curves/`): a control mesh whose NURSS limit surface
//!   interpolates them ([JOS 2003]);
//! - bicubic patches ([`PATCHES`], `examples/patches/`): C2 blending and N-sided hole
//!   filling ([Jiang et al.]).
//!
//! Every method writes its files (OBJ, GLB or JSON models, PNG pictures) into the output
//! directory and returns them with a caption that says what the picture shows and, where
//! the claim is a number, the number measured in this run (the G2 continuity report, a
//! blend's match with its patches, the pixels in which two compared pictures differ, the
//! curvature range); a method that does not apply to an input returns nothing (the page
//! leaves out empty groups). Then `index.html` shows them all, one section per input, one
//! group per method, two pictures side by side (compared pictures share a row, camera and
//! colour range), a click enlarging one, with relative links only (the directory can be
//! moved or served as it is).
//!
//! Adding a method for meshes is one entry in [`METHODS`]. Everything goes through library
//! calls (no subprocesses), with small rates so that the whole gallery takes about a minute
//! of processor time in a test build.

use std::fmt::Write as _;
use std::fs;
use std::path::Path;

use anyhow::{Context, Result};
use subsurf::blend::blend;
use subsurf::blend::fill_g1;
use subsurf::blend::{fill, patch_boundary, FillOptions};
use subsurf::curves::{interpolate_geometry, InterpolateOptions};
use subsurf::g2cap::{continuity_report, patches_json, G2Surface, G2SurfaceOptions};
use subsurf::io::parse_geometry;
use subsurf::io::write_groups_obj;
use subsurf::io::MeshFormat;
use subsurf::io::Up;
use subsurf::io::{parse_obj, write_obj, WriteOptions};
use subsurf::io::{write_tessellation, TessellationFormat, TessellationWriteOptions};
use subsurf::limit::FaceVaryingSurface;
use subsurf::limit::{self, tessellate, LimitSurface, SurfacePoint};
use subsurf::mesh::{FaceVaryingInterpolation, Options, PolyMesh};
use subsurf::nurbs::SourcedGeometry;
use subsurf::nurbs::{Geometry as NurbsGeometry, Surface};
use subsurf::regularity::{check_regularity, plot_image, Mode, RegularityOptions};
use subsurf::render::{
    render_detailed, render_surface, write_png, Geometry, Paint, Render, RgbImage, Shading,
};
use subsurf::render::{sample_curvature, Curvature, CurvatureKind};
use subsurf::scheme::Adjustable;
use subsurf::spline::QuadSpline;
use subsurf::{Mixed, Scheme, SubdivideOptions};

use super::subdivide::{command_line, refine, write};
use crate::input::Input;
use crate::output::Output;
use crate::progress::Progress;
use crate::DemoArgs;

/// What a bundled mesh is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// A surface control mesh: Catmull-Clark and every method built on it.
    Surface,
    /// A control mesh with knot intervals: non-uniform Catmull-Clark beside plain
    /// Catmull-Clark of the same cage.
    Knots,
    /// A planar net: the regularity certificate.
    Planar,
    /// A mesh of triangles: Loop beside Catmull-Clark of the same triangles.
    Triangles,
}

/// A bundled example mesh.
struct Example {
    name: &'static str,
    obj: &'static str,
    kind: Kind,
    /// Also refine to the limit surface, with normals.
    limit: bool,
    /// Samples per base edge for limit tessellations and pictures (small for big meshes).
    rate: u32,
    /// Camera azimuth and elevation of the pictures.
    view: (f64, f64),
}

macro_rules! example {
    ($name:literal, $kind:expr, $limit:expr, $rate:expr, $view:expr) => {
        Example {
            name: $name,
            obj: include_str!(concat!("../../../../examples/meshes/", $name, ".obj")),
            kind: $kind,
            limit: $limit,
            rate: $rate,
            view: $view,
        }
    };
}

const EXAMPLES: &[Example] = &[
    example!("cube", Kind::Surface, false, 8, (30.0, 20.0)),
    example!("cube-crease", Kind::Surface, false, 8, (30.0, 20.0)),
    example!("grid", Kind::Surface, false, 8, (30.0, 25.0)),
    example!("hut", Kind::Surface, false, 8, (30.0, 20.0)),
    example!("torus", Kind::Surface, true, 6, (30.0, 35.0)),
    example!("pentaprism", Kind::Surface, false, 6, (20.0, 35.0)),
    example!("catmark_pawn", Kind::Surface, false, 2, (30.0, 10.0)),
    example!("pawn-triangles", Kind::Triangles, false, 4, (30.0, 10.0)),
    example!("nurss-grid", Kind::Knots, false, 8, (30.0, 25.0)),
    example!("regularity-gear", Kind::Planar, false, 1, (0.0, 90.0)),
    example!("regularity-dolphin", Kind::Planar, false, 1, (0.0, 90.0)),
    example!("regularity-butterfly", Kind::Planar, false, 1, (0.0, 90.0)),
];

/// A bundled curve file for curve interpolation.
struct CurveExample {
    name: &'static str,
    json: &'static str,
    /// Zone width (relative to each curve's size).
    width: f64,
    /// Side direction of the zones (`None`: rotation-minimising frames).
    side: Option<[f64; 3]>,
    view: (f64, f64),
    /// Magnification of the pictures (the fitted view frames the bounding sphere).
    zoom: f64,
}

const CURVES: &[CurveExample] = &[
    CurveExample {
        name: "vase",
        json: include_str!("../../../../examples/curves/vase.json"),
        width: 0.05,
        side: None,
        view: (30.0, 20.0),
        zoom: 1.0,
    },
    CurveExample {
        name: "dolphin",
        json: include_str!("../../../../examples/curves/dolphin.json"),
        width: 0.08,
        side: None,
        view: (20.0, 45.0),
        // Long and thin: magnified to fill the picture's width.
        zoom: 1.3,
    },
];

/// What is done with a bundled patch file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PatchUse {
    /// C2 blend of the patches.
    Blend,
    /// Corner-interpolating hole filling bounded by the patches' first rows.
    Fill,
    /// Hole filling meeting the patches G1.
    FillG1,
}

/// A bundled patch file for blending or hole filling.
struct PatchExample {
    name: &'static str,
    json: &'static str,
    purpose: PatchUse,
    view: (f64, f64),
    /// Magnification of the pictures around the middle, where the new surface is.
    zoom: f64,
}

macro_rules! patches {
    ($name:literal, $purpose:expr, $view:expr, $zoom:expr) => {
        PatchExample {
            name: $name,
            json: include_str!(concat!("../../../../examples/patches/", $name, ".json")),
            purpose: $purpose,
            view: $view,
            zoom: $zoom,
        }
    };
}

const PATCHES: &[PatchExample] = &[
    patches!("blend3", PatchUse::Blend, (30.0, 50.0), 1.2),
    patches!("blend5", PatchUse::Blend, (30.0, 50.0), 1.2),
    patches!("hole3", PatchUse::Fill, (30.0, 40.0), 1.3),
    patches!("hole5", PatchUse::Fill, (30.0, 40.0), 1.3),
    patches!("hole3-g1", PatchUse::FillG1, (30.0, 40.0), 1.3),
    patches!("hole5-g1", PatchUse::FillG1, (30.0, 40.0), 1.3),
];

/// One method of the gallery for meshes.
struct Method {
    /// Heading of the method's files in the page.
    name: &'static str,
    /// Writes the method's files for one example; returns them with their captions
    /// (nothing when the method does not apply to the example).
    run: fn(&Ctx) -> Result<Vec<Item>>,
}

/// The methods shown for meshes, in page order. Add a method here.
const METHODS: &[Method] = &[
    Method {
        name: "Catmull-Clark refinement",
        run: catmull_clark,
    },
    Method {
        name: "Exact limit surface",
        run: limit_surface,
    },
    Method {
        name: "Pictures of the limit surface",
        run: pictures,
    },
    Method {
        name: TEXTURE,
        run: texture,
    },
    Method {
        name: LOOP,
        run: loop_scheme,
    },
    Method {
        name: "Shape-adjustable Catmull-Clark",
        run: adjustable,
    },
    Method {
        name: NURSS,
        run: nurss,
    },
    Method {
        name: G2,
        run: g2_caps,
    },
    Method {
        name: SPLINE,
        run: spline,
    },
    Method {
        name: REGULARITY,
        run: regularity,
    },
];

/// Headings of the methods that are not on meshes (and of some that are, for tests).
const NURSS: &str = "Non-uniform Catmull-Clark (NURSS)";
const TEXTURE: &str = "Texture coordinates";
const LOOP: &str = "Loop subdivision of triangles";
const G2: &str = "G2 caps at extraordinary vertices";
const SPLINE: &str = "Sub-basis spline surface";
const REGULARITY: &str = "Regularity certificate";
const INTERPOLATION: &str = "Curve interpolation";
const BLENDING: &str = "C2 blending of patches";
const FILLING: &str = "N-sided hole filling";

/// Refinement level of the demo.
const LEVELS: u32 = 3;
/// Picture size (the page shows two side by side; a click shows one as large as the window).
const SIZE: (u32, u32) = (480, 360);
/// Shape parameters of the adjustable scheme shown (0.5 would be Catmull-Clark).
const ADJUSTABLE_C: [f64; 3] = [0.0, 0.25, 0.8];
/// Adjustable steps before Catmull-Clark in the mixed surfaces shown.
const ADJUSTABLE_STEPS: u32 = 1;
/// Level of the adjustable refinements written.
const ADJUSTABLE_LEVELS: u32 = 2;
/// Samples per edge of the G2 pictures (zebra stripes need a fine grid).
const G2_RATE: u32 = 16;
/// Sample points per cap boundary of the measured continuity in the G2 captions (as
/// `subsurf g2 --report`).
const G2_REPORT_SAMPLES: usize = 24;
/// Share of the samples whose mean curvature lies inside the colour range of the mean
/// curvature pictures: the rest are drawn in the end colours. On `catmark_pawn` the thin
/// bands along its semi-sharp creases hold about a tenth of the samples (small faces) with
/// |H| up to a thousand times the rest's: the 90th percentile of |H| is 1005, the 85th 32.
const CURVATURE_QUANTILE: f64 = 0.85;
/// G2 caps are shown on meshes with at most this many faces (the caps of a big mesh are
/// too small to see in the gallery's pictures, and its patch file is megabytes).
const G2_MAX_FACES: usize = 64;
/// Close-ups of the G2 pictures: example, camera (azimuth, elevation) looking straight at
/// an extraordinary vertex, zoom. Other examples use their own view.
const G2_CLOSEUPS: &[(&str, (f64, f64), f64)] = &[
    // The corner (1, 1, 1) of the cube, valence 3.
    ("cube", (45.0, 35.26), 1.5),
    // The centre of the top pentagon, valence 5, from above.
    ("pentaprism", (0.0, 90.0), 1.2),
];
/// Camera of the NURSS pictures: low and from the side, so that the bump of the grid shows.
const NURSS_VIEW: (f64, f64) = (-60.0, 30.0);
/// Magnification of the NURSS pictures (the grid is flat but for a low bump).
const NURSS_ZOOM: f64 = 1.5;
/// NURSS levels of the curve interpolations' limit meshes.
const CURVE_LEVELS: u32 = 4;
/// Skirt-removal levels of blends and fills.
const PATCH_LEVELS: u32 = 4;
/// Segments per knot span of the tessellated base patches.
const PATCH_SAMPLES: u32 = 6;
/// Samples per face side of the regularity certificate's ground truth.
const REGULARITY_SAMPLES: usize = 5;

/// What a method gets: the example, its parsed mesh and scheme options, where to write.
struct Ctx<'a> {
    dir: &'a Path,
    ex: &'a Example,
    input: &'a Input,
    options: Options,
}

/// One input's part of the page: its name and, per method, the method's files.
type Section<'a> = (&'a str, Vec<(&'a str, Vec<Item>)>);

/// A written file and its one-line caption; `counts` (vertices, faces) for OBJ files.
struct Item {
    file: String,
    caption: String,
    counts: Option<(usize, usize)>,
}

/// Picture options: the gallery's size, `geometry`, `paint` and camera `view`.
fn picture(geometry: Geometry, paint: Paint, view: (f64, f64)) -> Render {
    Render {
        width: SIZE.0,
        height: SIZE.1,
        supersampling: 2,
        geometry,
        paint,
        view,
        ..Render::default()
    }
}

/// Writes `image` as the PNG `file` of `dir`.
fn png_item(dir: &Path, image: &RgbImage, file: String, caption: String) -> Result<Item> {
    Output::File(dir.join(&file)).write(|w| write_png(w, image))?;
    Ok(Item {
        file,
        caption,
        counts: None,
    })
}

/// Writes `mesh` (with its tags) as the OBJ `file` of `dir` with a header `comment`.
fn obj_item(
    dir: &Path,
    mesh: &PolyMesh,
    scheme: Option<Options>,
    file: String,
    comment: &str,
    caption: String,
) -> Result<Item> {
    let opts = WriteOptions {
        normals: None,
        scheme,
        comment: Some(comment),
    };
    Output::File(dir.join(&file)).write(|mut w| write_obj(&mut w, mesh, &opts))?;
    Ok(Item {
        file,
        caption,
        counts: Some((mesh.num_vertices(), mesh.num_faces())),
    })
}

/// Copies a bundled input file into `dir`.
fn source_item(
    dir: &Path,
    file: String,
    text: &str,
    counts: Option<(usize, usize)>,
) -> Result<Item> {
    Output::File(dir.join(&file)).write(|w| w.write_all(text.as_bytes()))?;
    Ok(Item {
        file,
        caption: "input".to_owned(),
        counts,
    })
}

/// How a dense mesh is shown: camera, zoom, and whether its own edges are drawn on the
/// shaded picture (to show how the vertices are spaced).
#[derive(Clone, Copy)]
struct Look {
    view: (f64, f64),
    zoom: f64,
    edges: bool,
}

/// Pictures of a dense mesh drawn as it is (a sampled limit surface): shaded (`what`) and
/// zebra stripes (`zebra`, the caption saying what the stripes show).
fn dense_pictures(
    dir: &Path,
    mesh: &PolyMesh,
    look: Look,
    stem: &str,
    (what, zebra): (&str, &str),
) -> Result<Vec<Item>> {
    let mut items = Vec::new();
    for (paint, suffix, caption) in [
        (Paint::Plain, "shaded", format!("{what}, shaded")),
        (
            Paint::Zebra,
            "zebra",
            format!("{what}, zebra stripes: {zebra}"),
        ),
    ] {
        let opts = Render {
            zoom: look.zoom,
            control_mesh: look.edges && paint == Paint::Plain,
            ..picture(Geometry::Level(0), paint, look.view)
        };
        let r = render_detailed(mesh, &Options::default(), &opts)
            .with_context(|| format!("{stem}: {suffix} picture"))?;
        items.push(png_item(
            dir,
            &r.image,
            format!("{stem}-{suffix}.png"),
            caption,
        )?);
    }
    Ok(items)
}

impl Ctx<'_> {
    fn mesh(&self) -> &PolyMesh {
        &self.input.obj.mesh
    }

    /// `<example>-<suffix>`.
    fn file(&self, suffix: &str) -> String {
        format!("{}-{suffix}", self.ex.name)
    }

    /// Picture options for this example (its limit surface).
    fn picture(&self, paint: Paint) -> Render {
        picture(Geometry::Limit { rate: self.ex.rate }, paint, self.ex.view)
    }

    /// Renders `mesh` with `opts` to the PNG `file`.
    fn png(&self, mesh: &PolyMesh, opts: &Render, file: &str, caption: String) -> Result<Item> {
        let r = render_detailed(mesh, &self.options, opts)
            .with_context(|| format!("{}: {file}", self.input.name))?;
        png_item(self.dir, &r.image, file.to_owned(), caption)
    }

    /// Writes `mesh` as OBJ to `file` with a header `comment`.
    fn obj(&self, mesh: &PolyMesh, file: &str, comment: &str, caption: String) -> Result<Item> {
        obj_item(
            self.dir,
            mesh,
            Some(self.options),
            file.to_owned(),
            comment,
            caption,
        )
    }

    /// Whether Catmull-Clark and the methods on its limit surface are shown.
    fn surface(&self) -> bool {
        matches!(self.ex.kind, Kind::Surface | Kind::Knots)
    }
}

/// Runs `subsurf demo`.
pub fn run(args: &DemoArgs) -> Result<()> {
    let dir = &args.output;
    fs::create_dir_all(dir)
        .with_context(|| format!("cannot create directory {}", dir.display()))?;
    let mut stdout = std::io::stdout().lock();
    let mut sections: Vec<Section> = Vec::new();
    // Reports a section's files and adds it to the page.
    let mut show = |name: &'static str, groups: Vec<(&'static str, Vec<Item>)>| -> Result<()> {
        for item in groups.iter().flat_map(|g| &g.1) {
            report(&mut stdout, dir, item)?;
        }
        sections.push((name, groups));
        Ok(())
    };
    for ex in EXAMPLES {
        let name = format!("{}.obj", ex.name);
        let input = Input {
            obj: parse_obj(ex.obj.as_bytes(), &name)?,
            name,
            format: MeshFormat::Obj,
            ignored: Vec::new(),
        };
        let m = &input.obj.mesh;
        let source = source_item(
            dir,
            input.name.clone(),
            ex.obj,
            Some((m.num_vertices(), m.num_faces())),
        )?;
        let ctx = Ctx {
            dir,
            ex,
            input: &input,
            options: input.obj.options.resolve(Options::default()),
        };
        let mut groups = vec![("Input", vec![source])];
        for method in METHODS {
            let items =
                (method.run)(&ctx).with_context(|| format!("{}: {}", ex.name, method.name))?;
            groups.push((method.name, items));
        }
        show(ex.name, groups)?;
    }
    for ex in CURVES {
        let source = source_item(dir, format!("{}.json", ex.name), ex.json, None)?;
        let items =
            interpolation(dir, ex).with_context(|| format!("{}: {INTERPOLATION}", ex.name))?;
        show(
            ex.name,
            vec![("Input", vec![source]), (INTERPOLATION, items)],
        )?;
    }
    for ex in PATCHES {
        let source = source_item(dir, format!("{}.json", ex.name), ex.json, None)?;
        let heading = match ex.purpose {
            PatchUse::Blend => BLENDING,
            PatchUse::Fill | PatchUse::FillG1 => FILLING,
        };
        let items = patch_method(dir, ex).with_context(|| format!("{}: {heading}", ex.name))?;
        show(ex.name, vec![("Input", vec![source]), (heading, items)])?;
    }
    let index = Item {
        file: "index.html".to_owned(),
        caption: "the gallery: open in a browser".to_owned(),
        counts: None,
    };
    let html = gallery_html(&sections);
    Output::File(dir.join(&index.file)).write(|w| w.write_all(html.as_bytes()))?;
    report(&mut stdout, dir, &index)
}

/// One line per written file: path, counts (OBJ), caption.
fn report(out: &mut impl std::io::Write, dir: &Path, item: &Item) -> Result<()> {
    let path = dir.join(&item.file);
    match item.counts {
        Some((v, f)) => writeln!(
            out,
            "{}  {v} vertices, {f} faces ({})",
            path.display(),
            item.caption
        ),
        None => writeln!(out, "{}  ({})", path.display(), item.caption),
    }
    .context("cannot write to standard output")
}

// ---------------------------------------------------------------------------------------
// Methods on meshes.

/// Catmull-Clark refinement to level 3 (and, for some examples, to the limit with normals).
fn catmull_clark(ctx: &Ctx) -> Result<Vec<Item>> {
    if !ctx.surface() {
        return Ok(Vec::new());
    }
    let mut items = Vec::new();
    for limit in [false, true].into_iter().filter(|&l| !l || ctx.ex.limit) {
        let opts = SubdivideOptions {
            levels: LEVELS,
            options: ctx.options,
            limit,
            ..Default::default()
        };
        let suffix = if limit { "-limit" } else { "" };
        let file = ctx.file(&format!("l{LEVELS}{suffix}.obj"));
        let progress = Progress::new(LEVELS, true);
        let sub = refine(ctx.input, &opts, &progress, true)?;
        let comment = command_line(&opts, &ctx.input.name);
        write(
            &Output::File(ctx.dir.join(&file)),
            &sub,
            &opts,
            &comment,
            &progress,
        )?;
        let m = &sub.mesh;
        let uniform = if ctx.ex.kind == Kind::Knots {
            " (uniform: knot intervals ignored)"
        } else {
            ""
        };
        items.push(Item {
            file,
            caption: if limit {
                format!("level {LEVELS}, limit positions and normals{uniform}")
            } else {
                format!("level {LEVELS}{uniform}")
            },
            counts: Some((m.num_vertices(), m.num_faces())),
        });
    }
    Ok(items)
}

/// The exact limit surface, tessellated watertight, as binary glTF with the control mesh.
fn limit_surface(ctx: &Ctx) -> Result<Vec<Item>> {
    if !ctx.surface() {
        return Ok(Vec::new());
    }
    let mesh = ctx.mesh();
    let rate = ctx.ex.rate;
    let surface = LimitSurface::new(mesh, ctx.options)?;
    let mut t = tessellate(&surface, mesh, rate, true)?;
    if let Some(c) = (mesh.face_varying.iter()).position(|c| c.name() == "uv") {
        let uv = FaceVaryingSurface::new(mesh, ctx.options, c)?;
        let values = t.evaluate_face_varying(mesh, &uv, "uv")?;
        t.face_varying.push(values);
    }
    let options = TessellationWriteOptions {
        control: Some(mesh),
        // The examples are Z-up, as the pictures draw them: turned to glTF's +Y up.
        up: Up::Z,
        ..Default::default()
    };
    let file = ctx.file("limit.glb");
    Output::File(ctx.dir.join(&file))
        .write(|mut w| write_tessellation(&mut w, TessellationFormat::Glb, &t, &options))?;
    Ok(vec![Item {
        file,
        caption: format!(
            "exact limit surface, {} samples per edge, with the control mesh (glTF; the viewer in viewer/ opens it)",
            t.rate
        ),
        counts: None,
    }])
}

/// Shaded with the control mesh, zebra stripes, mean curvature.
fn pictures(ctx: &Ctx) -> Result<Vec<Item>> {
    if !ctx.surface() {
        return Ok(Vec::new());
    }
    let shaded = Render {
        control_mesh: true,
        ..ctx.picture(Paint::Plain)
    };
    let what = if ctx.ex.kind == Kind::Knots {
        "uniform Catmull-Clark limit surface (knot intervals ignored)"
    } else {
        "limit surface"
    };
    Ok(vec![
        ctx.png(
            ctx.mesh(),
            &shaded,
            &ctx.file("shaded.png"),
            format!("{what}, shaded, with the control mesh"),
        )?,
        ctx.png(
            ctx.mesh(),
            &ctx.picture(Paint::Zebra),
            &ctx.file("zebra.png"),
            "zebra stripes (reflection lines): broken at a kink, kinked at a curvature jump"
                .to_owned(),
        )?,
        mean_curvature(ctx)?,
    ])
}

/// Samples per face diagonal of the curvature profile through an extraordinary vertex.
const PROFILE_SAMPLES: usize = 200;
/// The profile's samples nearest the vertex, in units of the face diagonal (at the vertex
/// itself Catmull-Clark's curvature is not defined).
const PROFILE_NEAREST: f64 = 1e-3;

/// The Gaussian curvature of Catmull-Clark and of the G2 caps along a path through the
/// first capped extraordinary vertex, inside one of its faces: along the face's edge
/// towards the vertex, then along the face's diagonal away from it. Approached along
/// different directions, Catmull-Clark's curvature at such a vertex differs (the lobes of
/// the curvature pictures), the caps' does not. Plotted as SVG, the values either side of
/// the vertex in the caption. `None` when no quad has the vertex.
fn curvature_profile(ctx: &Ctx, g2: &G2Surface) -> Result<Option<Item>> {
    let mesh = ctx.mesh();
    let Some(v) = g2.caps().iter().find_map(|c| c.vertex) else {
        return Ok(None);
    };
    // A quad with `v`, and `v`'s corner in it.
    let Some((face, i)) = (0..mesh.num_faces())
        .filter(|&f| mesh.face(f).len() == 4)
        .find_map(|f| (mesh.face(f).iter().position(|&x| x as usize == v)).map(|i| (f, i)))
    else {
        return Ok(None);
    };
    let cc = LimitSurface::new(mesh, ctx.options)?;
    // The point at `s` from corner `i` towards corner `i + k` (1: along the edge, 2: along
    // the diagonal).
    let at = |k: usize, s: f64| {
        let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let (a, b) = (c[i], c[(i + k) % 4]);
        SurfacePoint {
            face: face as u32,
            subface: 0,
            u: a.0 + s * (b.0 - a.0),
            v: a.1 + s * (b.1 - a.1),
        }
    };
    let profile = |surface: &dyn limit::Surface| -> Result<Vec<(f64, f64)>> {
        let mut out = Vec::with_capacity(2 * PROFILE_SAMPLES);
        for (k, sign) in [(1, -1.0), (2, 1.0)] {
            for j in 0..PROFILE_SAMPLES {
                let s = PROFILE_NEAREST
                    + (1.0 - PROFILE_NEAREST) * j as f64 / (PROFILE_SAMPLES - 1) as f64;
                let d = surface.evaluate(at(k, s))?;
                if let Some(c) = Curvature::from_derivatives(&d) {
                    out.push((sign * s, c.gauss));
                }
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(out)
    };
    let (ours, theirs) = (profile(g2)?, profile(&cc)?);
    // The values nearest the vertex from either side.
    let sides = |p: &[(f64, f64)]| {
        let before = p.iter().rev().find(|x| x.0 < 0.0).map_or(f64::NAN, |x| x.1);
        let after = p.iter().find(|x| x.0 > 0.0).map_or(f64::NAN, |x| x.1);
        (before, after)
    };
    let ((g_a, g_b), (c_a, c_b)) = (sides(&ours), sides(&theirs));
    let svg = profile_svg(
        &[
            ("Catmull-Clark", "#c0392b", &theirs),
            ("G2 caps", "#1f4fbf", &ours),
        ],
        &format!("Gaussian curvature through vertex {v}: along an edge, then a diagonal"),
        &format!(
            "along the edge of face {face} (left), along its diagonal (right); the vertex at 0"
        ),
    );
    let file = ctx.file("g2-profile.svg");
    Output::File(ctx.dir.join(&file)).write(|w| w.write_all(svg.as_bytes()))?;
    Ok(Some(Item {
        file,
        caption: format!(
            "Gaussian curvature through the capped vertex {v} (at 0), inside face {face}: \
             along its edge to the vertex, then along its diagonal away. At {PROFILE_NEAREST} \
             of a side from the vertex Catmull-Clark gives {c_a:.3} along the edge and \
             {c_b:.3} along the diagonal (a jump of {:.1} %), the G2 caps {g_a:.3} and \
             {g_b:.3} ({:.1} %)",
            100.0 * (c_a - c_b).abs() / c_a.abs().max(c_b.abs()),
            100.0 * (g_a - g_b).abs() / g_a.abs().max(g_b.abs()),
        ),
        counts: None,
    }))
}

/// A plotted series: its name, colour and points `(x, y)` sorted by `x`.
type Series<'a> = (&'a str, &'a str, &'a [(f64, f64)]);

/// A line plot of `series` (name, colour, points sorted by x) as an SVG of the gallery's
/// size, x from −1 to 1 (labelled `x_label`), y over the values' range, with a legend and
/// `title`; each series is drawn in two pieces, either side of x = 0.
fn profile_svg(series: &[Series<'_>], title: &str, x_label: &str) -> String {
    let (w, h) = (f64::from(SIZE.0), f64::from(SIZE.1));
    let (left, right, top, bottom) = (64.0, 16.0, 36.0, 48.0);
    let values = series.iter().flat_map(|s| s.2.iter().map(|p| p.1));
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
        (a.min(y), b.max(y))
    });
    let pad = 0.05 * (hi - lo).max(1e-9);
    let (lo, hi) = (lo - pad, hi + pad);
    let x = |t: f64| left + (t + 1.0) / 2.0 * (w - left - right);
    let y = |v: f64| top + (hi - v) / (hi - lo) * (h - top - bottom);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n\
         <text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"13\">{}</text>\n",
        w / 2.0,
        escape(title)
    );
    // Axes: the frame, the vertex at x = 0, and y ticks at the range's ends and zero.
    let _ = writeln!(
        svg,
        "<rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" \
         stroke=\"#888\"/>\n<line x1=\"{x0}\" x2=\"{x0}\" y1=\"{top}\" y2=\"{}\" \
         stroke=\"#888\" stroke-dasharray=\"4 3\"/>",
        w - left - right,
        h - top - bottom,
        h - bottom,
        x0 = x(0.0),
    );
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
        w / 2.0,
        h - 14.0,
        escape(x_label)
    );
    for v in [lo + pad, 0.0, hi - pad]
        .into_iter()
        .filter(|v| (lo..=hi).contains(v))
    {
        let _ = writeln!(
            svg,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{v:.2}</text>",
            left - 6.0,
            y(v) + 4.0
        );
    }
    for (k, (name, colour, points)) in series.iter().enumerate() {
        let path: Vec<String> = (points.iter())
            .map(|&(t, v)| format!("{:.2},{:.2}", x(t), y(v)))
            .collect();
        // Two pieces, either side of the vertex: the curvature is not joined across it.
        let split = points
            .iter()
            .position(|p| p.0 > 0.0)
            .unwrap_or(points.len());
        for piece in [&path[..split], &path[split..]] {
            if piece.len() > 1 {
                let _ = writeln!(
                    svg,
                    "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\" \
                     points=\"{}\"/>",
                    piece.join(" ")
                );
            }
        }
        let ly = top + 16.0 + 16.0 * k as f64;
        let _ = writeln!(
            svg,
            "<line x1=\"{}\" x2=\"{}\" y1=\"{ly}\" y2=\"{ly}\" stroke=\"{colour}\" \
             stroke-width=\"2\"/><text x=\"{}\" y=\"{}\">{}</text>",
            left + 10.0,
            left + 34.0,
            left + 40.0,
            ly + 4.0,
            escape(name)
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Squares per side of the unit square of texture coordinates in the checker pictures.
const CHECKER_SQUARES: u32 = 8;

/// Texture coordinates through refinement and at the limit: a checker on the control mesh,
/// on the limit surface in the example's face-varying mode, and in mode `none` (`all` if
/// that is the example's), with the largest difference of the two limits measured at the
/// tessellation's corners.
fn texture(ctx: &Ctx) -> Result<Vec<Item>> {
    let mesh = ctx.mesh();
    let Some(channel) = (mesh.face_varying.iter()).position(|c| c.name() == "uv") else {
        return Ok(Vec::new());
    };
    let checker = Paint::Checker {
        squares: CHECKER_SQUARES,
    };
    let control = Render {
        shading: Shading::Flat,
        control_mesh: true,
        ..picture(Geometry::Level(0), checker, ctx.ex.view)
    };
    let values = mesh.face_varying[channel].num_values();
    let mode = ctx.options.face_varying;
    // The other extreme: smooth everywhere, or linear everywhere.
    let other_mode = match mode {
        FaceVaryingInterpolation::None => FaceVaryingInterpolation::All,
        _ => FaceVaryingInterpolation::None,
    };
    let other = Options {
        face_varying: other_mode,
        ..ctx.options
    };
    // Where the two limits differ most, over the limit tessellation's corners.
    let surface = LimitSurface::new(mesh, ctx.options)?;
    let t = tessellate(&surface, mesh, ctx.ex.rate, false)?;
    let uv = |o: Options| -> Result<Vec<[f64; 2]>> {
        let s = FaceVaryingSurface::new(mesh, o, channel)?;
        let ch = t.evaluate_face_varying(mesh, &s, "uv")?;
        Ok((ch.indices().iter())
            .map(|&k| {
                let x = ch.value(k as usize);
                [x[0], x[1]]
            })
            .collect())
    };
    let (a, b) = (uv(ctx.options)?, uv(other)?);
    let moved = (a.iter().zip(&b))
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0f64, f64::max);
    let limit_mode = ctx.picture(checker);
    let draw = |o: &Options, what: &str| {
        render_detailed(mesh, o, &limit_mode)
            .map(|r| r.image)
            .with_context(|| format!("{}: texture, mode {what}", ctx.input.name))
    };
    let at_mode = draw(&ctx.options, &mode.to_string())?;
    let at_other = draw(&other, &other_mode.to_string())?;
    let differ = differing_pixels(&at_mode, &at_other);
    let at_mode = png_item(
        ctx.dir,
        &at_mode,
        ctx.file(&format!("texture-{mode}.png")),
        format!(
            "exact limit surface, the checker through the texture coordinates' exact limit \
             (mode {mode})"
        ),
    )?;
    let at_other = png_item(
        ctx.dir,
        &at_other,
        ctx.file(&format!("texture-{other_mode}.png")),
        format!(
            "mode {other_mode}: the texture moves by up to {moved:.3} of the unit square from \
             mode {mode}'s; {:.1} % of the pixels differ",
            100.0 * differ
        ),
    )?;
    Ok(vec![
        ctx.png(
            mesh,
            &control,
            &ctx.file("texture-control.png"),
            format!(
                "control mesh, a {CHECKER_SQUARES} × {CHECKER_SQUARES} checker through its \
                 {values} texture coordinates (vt)"
            ),
        )?,
        at_mode,
        at_other,
    ])
}

/// Loop beside Catmull-Clark on a mesh of triangles: the reflection lines and the mean
/// curvature of both exact limit surfaces, the curvature on one colour range (holding
/// [`CURVATURE_QUANTILE`] of both surfaces' samples), with the spread of each measured.
fn loop_scheme(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Triangles {
        return Ok(Vec::new());
    }
    let mesh = ctx.mesh();
    let schemes = [
        (Scheme::Loop, "loop", "Loop"),
        (Scheme::CatmullClark, "cc", "Catmull-Clark"),
    ];
    let mut mean = Vec::new();
    for (scheme, _, name) in schemes {
        let samples = sample_curvature(mesh, &ctx.options, scheme, ctx.ex.rate)
            .with_context(|| format!("{}: {name} curvature samples", ctx.input.name))?;
        let mut h: Vec<f64> = (samples.iter())
            .filter_map(|s| s.curvature.map(|c| c.mean))
            .filter(|h| h.is_finite())
            .collect();
        h.sort_unstable_by(f64::total_cmp);
        mean.push(h);
    }
    let quantile = |v: &[f64], q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    let mut size: Vec<f64> = mean.iter().flatten().map(|h| h.abs()).collect();
    if size.is_empty() {
        anyhow::bail!("{}: no curvature samples", ctx.input.name);
    }
    size.sort_unstable_by(f64::total_cmp);
    let bound = match quantile(&size, CURVATURE_QUANTILE) {
        b if b > 0.0 => b,
        _ => 1.0,
    };
    let mut items = Vec::new();
    for ((scheme, tag, name), h) in schemes.into_iter().zip(&mean) {
        let zebra = Render {
            scheme,
            ..ctx.picture(Paint::Zebra)
        };
        let what = match scheme {
            Scheme::Loop => "Loop limit surface (a quartic box spline over each regular triangle)",
            _ => "Catmull-Clark limit surface of the same triangles (each split into three quads)",
        };
        items.push(ctx.png(
            mesh,
            &zebra,
            &ctx.file(&format!("{tag}-zebra.png")),
            format!("{what}: reflection lines"),
        )?);
        let curvature = Render {
            scheme,
            curvature_range: Some((-bound, bound)),
            ..ctx.picture(Paint::Curvature(CurvatureKind::Mean))
        };
        let spread = quantile(h, 0.75) - quantile(h, 0.25);
        items.push(ctx.png(
            mesh,
            &curvature,
            &ctx.file(&format!("{tag}-curvature.png")),
            format!(
                "{name}: mean curvature H, both surfaces on one colour range |H| ≤ {bound:.3}; \
                 the middle half of its {n} samples spans {spread:.3}",
                n = h.len()
            ),
        )?);
    }
    Ok(items)
}

/// Mean curvature of the exact limit surface, its colour range holding
/// [`CURVATURE_QUANTILE`] of the samples, with the measured spread in the caption.
fn mean_curvature(ctx: &Ctx) -> Result<Item> {
    let samples = sample_curvature(ctx.mesh(), &ctx.options, Scheme::CatmullClark, ctx.ex.rate)
        .with_context(|| format!("{}: curvature samples", ctx.input.name))?;
    let mut size: Vec<f64> = samples
        .iter()
        .filter_map(|s| s.curvature.map(|c| c.mean.abs()))
        .filter(|h| h.is_finite())
        .collect();
    size.sort_unstable_by(f64::total_cmp);
    let at = |q: f64| size[((size.len() - 1) as f64 * q).round() as usize];
    let (bound, largest) = match size.last() {
        Some(&largest) => (at(CURVATURE_QUANTILE), largest),
        None => anyhow::bail!("{}: no curvature samples", ctx.input.name),
    };
    let bound = if bound > 0.0 { bound } else { largest.max(1.0) };
    let opts = Render {
        curvature_range: Some((-bound, bound)),
        ..ctx.picture(Paint::Curvature(CurvatureKind::Mean))
    };
    ctx.png(
        ctx.mesh(),
        &opts,
        &ctx.file("curvature.png"),
        format!(
            "mean curvature H of the exact limit surface (red convex, blue concave); the \
             colours span |H| ≤ {bound:.3}, which holds {pct:.0} % of the {n} samples (the \
             largest |H| is {largest:.3}: those beyond are drawn in the end colours)",
            pct = 100.0 * CURVATURE_QUANTILE,
            n = size.len()
        ),
    )
}

/// The adjustable scheme for a few `c`: the level-2 refinement, and a picture of the
/// mixed surface (one step with `c`, then Catmull-Clark to the limit).
fn adjustable(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Surface {
        return Ok(Vec::new());
    }
    let mut items = Vec::new();
    for c in ADJUSTABLE_C {
        let all = Mixed::all(Adjustable::new(c)?);
        let opts = SubdivideOptions {
            levels: ADJUSTABLE_LEVELS,
            scheme: Scheme::Adjustable(all),
            options: ctx.options,
            ..Default::default()
        };
        let progress = Progress::new(ADJUSTABLE_LEVELS, true);
        let sub = refine(ctx.input, &opts, &progress, true)?;
        let comment = format!(
            "{} {}",
            command_line(&opts, &ctx.input.name),
            super::adjustable::flags(all, ADJUSTABLE_LEVELS)
        );
        items.push(ctx.obj(
            &sub.mesh,
            &ctx.file(&format!("c{c}-l{ADJUSTABLE_LEVELS}.obj")),
            &comment,
            format!(
                "adjustable scheme, c = {c}, level {ADJUSTABLE_LEVELS} (c = 0.5 is Catmull-Clark)"
            ),
        )?);

        let mixed = Mixed {
            steps: ADJUSTABLE_STEPS,
            ..all
        };
        let refined = super::adjustable::refined_mesh(ctx.input, ctx.options, mixed)?;
        let rate = super::adjustable::refined_rate(ctx.ex.rate, ADJUSTABLE_STEPS);
        let pic = Render {
            geometry: Geometry::Limit { rate },
            ..ctx.picture(Paint::Zebra)
        };
        items.push(ctx.png(
            &refined,
            &pic,
            &ctx.file(&format!("c{c}-zebra.png")),
            format!(
                "mixed surface, c = {c}: {ADJUSTABLE_STEPS} step with c, then Catmull-Clark \
                 (zebra; compare with the Catmull-Clark zebra above)"
            ),
        )?);
    }
    Ok(items)
}

/// Non-uniform Catmull-Clark with the file's knot intervals: the refined mesh (with its
/// refined intervals), its limit positions, and pictures of the latter.
fn nurss(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Knots {
        return Ok(Vec::new());
    }
    let mut items = Vec::new();
    let mut limit_mesh = None;
    for limit in [false, true] {
        let opts = SubdivideOptions {
            levels: LEVELS,
            scheme: Scheme::Nurss,
            options: ctx.options,
            limit,
            ..Default::default()
        };
        let sub = subsurf::subdivide(ctx.mesh(), &opts)?;
        let (suffix, what) = if limit {
            ("nurss-limit", ", moved to the limit surface")
        } else {
            ("nurss-l3", " with the refined knot intervals (t interval)")
        };
        items.push(ctx.obj(
            &sub.mesh,
            &ctx.file(&format!("{suffix}.obj")),
            &format!(
                "subsurf subdivide --scheme nurss -l {LEVELS}{} {}",
                if limit { " --limit" } else { "" },
                ctx.input.name
            ),
            format!("NURSS level {LEVELS}{what}"),
        )?);
        if limit {
            limit_mesh = Some(sub.mesh);
        }
    }
    let limit = limit_mesh.context("no limit mesh")?;
    let look = Look {
        view: NURSS_VIEW,
        zoom: NURSS_ZOOM,
        edges: false,
    };
    items.extend(dense_pictures(
        ctx.dir,
        &limit,
        look,
        &ctx.file("nurss"),
        (
            "NURSS limit surface",
            "the reflection lines of the non-uniform surface",
        ),
    )?);
    items.push(nurss_spacing(ctx)?);
    Ok(items)
}

/// The NURSS mesh after two steps with its edges, flat shaded: the refined vertices keep
/// the spacing of the knot intervals.
fn nurss_spacing(ctx: &Ctx) -> Result<Item> {
    let opts = SubdivideOptions {
        levels: 2,
        scheme: Scheme::Nurss,
        options: ctx.options,
        ..Default::default()
    };
    let sub = subsurf::subdivide(ctx.mesh(), &opts)?;
    let pic = Render {
        shading: subsurf::render::Shading::Flat,
        control_mesh: true,
        zoom: NURSS_ZOOM,
        ..picture(Geometry::Level(0), Paint::Plain, NURSS_VIEW)
    };
    ctx.png(
        &sub.mesh,
        &pic,
        &ctx.file("nurss-l2-edges.png"),
        "NURSS level 2 with its edges: the spans of the two middle columns (knot interval 3) \
         stay three times as wide as the others (interval 1), where uniform Catmull-Clark \
         would make them equal"
            .to_owned(),
    )
}

/// G2 caps: zebra and Gaussian curvature of the capped surface beside plain Catmull-Clark's
/// (same camera, same curvature colour range), and the caps' Bézier patches as JSON.
fn g2_caps(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Surface || ctx.mesh().num_faces() > G2_MAX_FACES {
        return Ok(Vec::new());
    }
    let mesh = ctx.mesh();
    let surface = G2Surface::new(
        mesh,
        &G2SurfaceOptions {
            options: ctx.options,
            ..Default::default()
        },
    )?;
    if surface.caps().is_empty() {
        return Ok(Vec::new());
    }
    let caps = surface.caps().len();
    let closeup = G2_CLOSEUPS.iter().find(|c| c.0 == ctx.ex.name);
    let place = if closeup.is_some() {
        "close-up of an extraordinary vertex"
    } else {
        "whole surface"
    };
    let (view, zoom) = closeup.map_or((ctx.ex.view, 1.0), |c| (c.1, c.2));
    let g2: &dyn limit::Surface = &surface;
    let draw = |paint: Paint, range: Option<(f64, f64)>, s: Option<&dyn limit::Surface>| {
        let opts = Render {
            curvature_range: range,
            zoom,
            ..picture(Geometry::Limit { rate: G2_RATE }, paint, view)
        };
        render_surface(mesh, &ctx.options, &opts, s)
            .with_context(|| format!("{}: G2 picture", ctx.input.name))
    };
    let gauss = Paint::Curvature(CurvatureKind::Gauss);
    let g2_zebra = draw(Paint::Zebra, None, Some(g2))?;
    let cc_zebra = draw(Paint::Zebra, None, None)?;
    let g2_curv = draw(gauss, None, Some(g2))?;
    let cc_curv = draw(gauss, g2_curv.curvature_range, None)?;
    let (lo, hi) = g2_curv.curvature_range.context("no curvature range")?;
    let report = continuity_report(&surface, G2_REPORT_SAMPLES)?;
    let differ = 100.0 * differing_pixels(&cc_zebra.image, &g2_zebra.image);
    let mut items = vec![
        png_item(
            ctx.dir,
            &cc_zebra.image,
            ctx.file("cc-zebra.png"),
            format!(
                "Catmull-Clark, {place}, zebra stripes: {differ:.1} % of the pixels differ \
                 from the G2 picture's. Both are G1 (the stripes do not break); the defect is \
                 in the curvature, which reflection lines show only faintly at this scale"
            ),
        )?,
        png_item(
            ctx.dir,
            &g2_zebra.image,
            ctx.file("g2-zebra.png"),
            format!("G2 caps ({caps} caps), same view, zebra stripes"),
        )?,
        png_item(
            ctx.dir,
            &cc_curv.image,
            ctx.file("cc-curvature.png"),
            format!(
                "Catmull-Clark, Gaussian curvature ({lo:.3} to {hi:.3}, the G2 picture's \
                 range): next to each of the {n} capped vertices the curvature depends on the \
                 direction of approach; the second fundamental forms of the patches there \
                 differ by up to {cc:.2} (relative, at 1e-3 of a patch from the vertex)",
                n = report.cc_vertex.boundaries,
                cc = report.cc_vertex.max_curvature_jump,
            ),
        )?,
        png_item(
            ctx.dir,
            &g2_curv.image,
            ctx.file("g2-curvature.png"),
            format!(
                "G2 caps, Gaussian curvature on the same range: measured jumps of the normal \
                 curvature (relative) {v:.1e} at the vertices, {i:.1e} across the caps' inner \
                 boundaries, {o:.1e} across their outer boundaries ({m} points per boundary)",
                v = report.g2_vertex.max_curvature_jump,
                i = report.g2_inner.max_curvature_jump,
                o = report.g2_outer.max_curvature_jump,
                m = G2_REPORT_SAMPLES,
            ),
        )?,
    ];
    if let Some(item) = curvature_profile(ctx, &surface)? {
        items.push(item);
    }
    items.push(g2_patches(ctx, &surface)?);
    Ok(items)
}

/// The Bézier control points of every patch of `surface` (the G2 surface of the example's
/// mesh), written as JSON.
fn g2_patches(ctx: &Ctx, surface: &G2Surface) -> Result<Item> {
    let doc = patches_json(surface, ctx.mesh())?;
    let file = ctx.file("g2.json");
    let text = doc.to_json();
    Output::File(ctx.dir.join(&file)).write(|w| writeln!(w, "{text}"))?;
    Ok(Item {
        file,
        caption: format!(
            "Bézier control points of every patch ({} caps of bi-septic patches, bicubic \
             B-spline elsewhere; schema in docs/adjustable-g2.md)",
            surface.caps().len()
        ),
        counts: None,
    })
}

/// The sub-basis spline on closed meshes without tags: its tessellation, and pictures with
/// the patches in alternating colours (as in the paper's Fig. 7) and as zebra stripes.
fn spline(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Surface || !ctx.mesh().tags.is_empty() {
        return Ok(Vec::new());
    }
    let spline = QuadSpline::new(ctx.mesh())?;
    let (mesh, surface) = (&spline.control, &spline.surface);
    if !(0..mesh.num_faces()).all(|f| surface.has_surface(f)) {
        // Faces at the boundary have no surface: show closed meshes only.
        return Ok(Vec::new());
    }
    let rate = ctx.ex.rate;
    let t = tessellate(surface, mesh, rate, false)?;
    let file = ctx.file("spline.obj");
    let comment = format!("subsurf spline --rate {rate} {}", ctx.input.name);
    let options = TessellationWriteOptions {
        comment: &comment,
        ..Default::default()
    };
    Output::File(ctx.dir.join(&file))
        .write(|mut w| write_tessellation(&mut w, TessellationFormat::Obj, &t, &options))?;
    let mut items = vec![Item {
        file,
        caption: format!("sub-basis spline surface, {rate} x {rate} quads per patch"),
        counts: Some((t.num_vertices(), t.num_faces())),
    }];
    let s: &dyn limit::Surface = surface;
    for (paint, suffix, caption) in [
        (
            Paint::Faces,
            "spline-patches.png",
            "one rational bicubic patch per face, neighbours in different colours",
        ),
        (
            Paint::Zebra,
            "spline-zebra.png",
            "sub-basis spline, zebra stripes (G1 at the irregular vertices)",
        ),
    ] {
        let opts = picture(Geometry::Limit { rate }, paint, ctx.ex.view);
        let r = render_surface(mesh, &ctx.options, &opts, Some(s))
            .with_context(|| format!("{}: spline picture", ctx.input.name))?;
        items.push(png_item(
            ctx.dir,
            &r.image,
            ctx.file(suffix),
            caption.to_owned(),
        )?);
    }
    Ok(items)
}

/// The regularity certificate of a planar net: its plot and the verdict.
fn regularity(ctx: &Ctx) -> Result<Vec<Item>> {
    if ctx.ex.kind != Kind::Planar {
        return Ok(Vec::new());
    }
    let mesh = ctx.mesh();
    let options = RegularityOptions {
        scheme: ctx.options,
        dimension: None,
        samples: REGULARITY_SAMPLES,
    };
    let report = check_regularity(mesh, &options)?;
    let mut items = Vec::new();
    for mode in [Mode::Local, Mode::Global] {
        let c = report.counts(mode);
        let (name, what) = match mode {
            Mode::Local => ("local", "per-face cones"),
            Mode::Global => ("global", "one cone pair per component"),
        };
        let verdict = if report.certified(mode) {
            "certified regular"
        } else {
            "not certified"
        };
        let img = plot_image(mesh, &report, mode);
        items.push(png_item(
            ctx.dir,
            &img,
            ctx.file(&format!("regularity-{name}.png")),
            format!(
                "{name} certificate ({what}): {verdict}; {} of {} faces certified, {} refused, \
                 {} not applicable (u-differences blue, v red)",
                c.certified,
                report.faces.len(),
                c.refused,
                c.not_applicable
            ),
        )?);
    }
    Ok(items)
}

// ---------------------------------------------------------------------------------------
// Curves and patches.

/// Curve interpolation: the control mesh with its knot intervals, the NURSS limit mesh,
/// and pictures of the latter.
fn interpolation(dir: &Path, ex: &CurveExample) -> Result<Vec<Item>> {
    let items = parse_geometry(ex.json.as_bytes(), &format!("{}.json", ex.name))?;
    let opts = InterpolateOptions {
        width: ex.width,
        side: ex.side,
    };
    let side = ex
        .side
        .map_or(String::new(), |[x, y, z]| format!(" --side {x},{y},{z}"));
    let zones = interpolate_geometry(&items, &opts)?;
    let limit = zones.limit_mesh(CURVE_LEVELS)?;
    let mut out = vec![
        obj_item(
            dir,
            &zones.mesh,
            None,
            format!("{}-control.obj", ex.name),
            &format!(
                "subsurf interpolate --width {}{side} {}.json --curve-samples 0",
                ex.width, ex.name
            ),
            format!(
                "control mesh, {} curve zone(s) of width {}, {}",
                zones.zones.len(),
                ex.width,
                if subsurf::nonuniform::has_knots(&zones.mesh) {
                    "with its knot intervals (t interval tags)"
                } else {
                    "uniform knots"
                }
            ),
        )?,
        obj_item(
            dir,
            &limit,
            None,
            format!("{}-limit.obj", ex.name),
            &format!(
                "subsurf interpolate --width {}{side} {}.json --tessellate \
                 --levels {CURVE_LEVELS} --curve-samples 0",
                ex.width, ex.name
            ),
            format!("NURSS limit surface ({CURVE_LEVELS} levels): passes through the curves"),
        )?,
    ];
    let look = Look {
        view: ex.view,
        zoom: ex.zoom,
        edges: false,
    };
    out.extend(dense_pictures(
        dir,
        &limit,
        look,
        ex.name,
        (
            "limit surface interpolating the curves",
            "the reflection lines of the limit surface",
        ),
    )?);
    Ok(out)
}

/// The bicubic patches of a patch file.
fn bspline_patches(items: &[SourcedGeometry]) -> Result<Vec<subsurf::nurbs::BSplineSurface<3>>> {
    items
        .iter()
        .map(|g| match &g.geometry {
            NurbsGeometry::Surface(Surface::BSpline(s)) => Ok(s.clone()),
            _ => anyhow::bail!("{}: not a bicubic B-spline patch", g.label()),
        })
        .collect()
}

/// Blending or hole filling: the base patches and the new surface as one OBJ with groups,
/// and pictures of all of them together.
fn patch_method(dir: &Path, ex: &PatchExample) -> Result<Vec<Item>> {
    let items = parse_geometry(ex.json.as_bytes(), &format!("{}.json", ex.name))?;
    let patches = bspline_patches(&items)?;
    let (surface, group, what, zebra) = match ex.purpose {
        PatchUse::Blend => {
            let b = blend(&patches, PATCH_LEVELS)?;
            let gap = blend_gap(&patches, &b)?;
            (
                b.surface()?,
                "blend",
                format!("C2 blend of {} patches", patches.len()),
                format!(
                    "the blend's exact limit meets every patch C2 along its first row: there, \
                     position, ∂/∂u and ∂²/∂u² of the two differ by at most {gap:.1e} \
                     ({BLEND_SAMPLES} points per patch); normals in the pictures are averaged \
                     from the sampled meshes"
                ),
            )
        }
        PatchUse::Fill => {
            let curves = patches
                .iter()
                .enumerate()
                .map(|(k, s)| patch_boundary(s, k))
                .collect::<Result<Vec<_>, _>>()?;
            (
                fill(&curves, PATCH_LEVELS, &FillOptions::default())?.surface()?,
                "fill",
                format!("{}-sided hole filled (corner interpolating)", patches.len()),
                "the fill passes through the patches' boundary curves and corners but does not \
                 take their tangent planes, so the stripes break at the seams"
                    .to_owned(),
            )
        }
        PatchUse::FillG1 => (
            fill_g1(&patches, PATCH_LEVELS, &FillOptions::default())?.surface()?,
            "fill",
            format!("{}-sided hole filled G1 to the patches", patches.len()),
            "the fill takes the patches' tangent planes along the seams (G1), not their \
             curvature; the boundary knots it triples for this leave creases inside the fill \
             next to the seams, where the stripes break up: G1 at the seams, not a fair \
             interior"
                .to_owned(),
        ),
    };
    let grids = patches
        .iter()
        .map(|s| Surface::BSpline(s.clone()).grid(PATCH_SAMPLES as usize))
        .collect::<Result<Vec<PolyMesh>, _>>()?;
    let mut groups: Vec<(String, &PolyMesh)> = grids
        .iter()
        .enumerate()
        .map(|(k, m)| (format!("patch_{}", k + 1), m))
        .collect();
    groups.push((group.to_owned(), &surface));
    let file = format!("{}-{group}.obj", ex.name);
    let comment = format!(
        "subsurf {} {}.json --levels {PATCH_LEVELS} --samples {PATCH_SAMPLES}{}",
        if group == "blend" { "blend" } else { "fill" },
        ex.name,
        if ex.purpose == PatchUse::FillG1 {
            " --g1"
        } else {
            ""
        }
    );
    Output::File(dir.join(&file)).write(|w| write_groups_obj(w, Some(&comment), &groups, &[]))?;
    let all = merge(groups.iter().map(|g| g.1))?;
    let mut out = vec![Item {
        file,
        caption: format!(
            "{what}: the base patches (groups patch_N) and the {group} surface after \
             {PATCH_LEVELS} skirt-removal levels"
        ),
        counts: Some((all.num_vertices(), all.num_faces())),
    }];
    let look = Look {
        view: ex.view,
        zoom: ex.zoom,
        edges: false,
    };
    out.extend(dense_pictures(dir, &all, look, ex.name, (&what, &zebra))?);
    Ok(out)
}

/// The share of pixels (0 to 1) in which pictures `a` and `b` of one size differ.
fn differing_pixels(a: &RgbImage, b: &RgbImage) -> f64 {
    let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    differ as f64 / (a.width() as f64 * a.height() as f64).max(1.0)
}

/// Points per patch at which [`blend_gap`] compares a blend with its patches.
const BLEND_SAMPLES: usize = 17;

/// The largest difference of position, `∂/∂u` and `∂²/∂u²` between each patch and the
/// blend's exact limit next to it ([`subsurf::blend::Blend::boundary_spline`]) on the
/// patch's first row `u = u_3`, at [`BLEND_SAMPLES`] points spread over `v`.
fn blend_gap(
    patches: &[subsurf::nurbs::BSplineSurface<3>],
    b: &subsurf::blend::Blend,
) -> Result<f64> {
    let mut worst = 0.0f64;
    for (k, patch) in patches.iter().enumerate() {
        let limit = b.boundary_spline(k)?;
        // The limit's domain ends at u_3; its refined knots may end an ulp short of the
        // patch's.
        let ((u, _), (a0, a1)) = patch.domain();
        let ((lu0, lu1), (b0, b1)) = limit.domain();
        let ul = u.clamp(lu0, lu1);
        let (v0, v1) = (a0.max(b0), a1.min(b1));
        for i in 0..BLEND_SAMPLES {
            let v = (v0 + (v1 - v0) * i as f64 / (BLEND_SAMPLES - 1) as f64).clamp(v0, v1);
            let (x, y) = (patch.eval_second(u, v)?, limit.eval_second(ul, v)?);
            for (a, c) in [(x.p, y.p), (x.du, y.du), (x.duu, y.duu)] {
                let d = (0..3).map(|j| (a[j] - c[j]).powi(2)).sum::<f64>().sqrt();
                worst = worst.max(d);
            }
        }
    }
    Ok(worst)
}

/// The meshes as one (disjoint) mesh.
fn merge<'a>(meshes: impl Iterator<Item = &'a PolyMesh>) -> Result<PolyMesh> {
    let (mut positions, mut offsets, mut verts) = (Vec::new(), vec![0u32], Vec::new());
    for m in meshes {
        let base = positions.len() as u32;
        positions.extend_from_slice(m.positions());
        for f in 0..m.num_faces() {
            verts.extend(m.face(f).iter().map(|&v| v + base));
            offsets.push(verts.len() as u32);
        }
    }
    PolyMesh::new(positions, offsets, verts).context("merged mesh")
}

// ---------------------------------------------------------------------------------------
// The page.

/// Escapes `&`, `<`, `>` and `"` for HTML text and attribute values.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(ch),
        }
    }
    out
}

/// Escapes a file name for an `href`/`src` attribute (names are ASCII letters, digits,
/// `.`, `-` and `_`; anything else is percent-encoded).
fn url(file: &str) -> String {
    let mut out = String::new();
    for b in file.bytes() {
        if b.is_ascii_alphanumeric() || b"-._".contains(&b) {
            out.push(b as char);
        } else {
            let _ = write!(out, "%{b:02X}");
        }
    }
    out
}

/// The self-contained gallery page: one section per example, one group per method;
/// pictures inline (each a link to itself), models as links; a caption for each.
fn gallery_html(sections: &[Section]) -> String {
    let mut h = String::new();
    h.push_str(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>subsurf demo gallery</title>\n<style>\n\
         body { font-family: sans-serif; margin: 1.5em; color: #222; background: #fafafa; }\n\
         section { margin-bottom: 2.5em; }\n\
         .grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(320px, 480px)); \
         gap: 1.2em; }\n\
         figure { margin: 0; }\n\
         figure img { display: block; width: 100%; height: auto; border: 1px solid #ccc; \
         background: #fff; cursor: zoom-in; }\n\
         figcaption { font-size: 0.85em; margin-top: 0.3em; }\n\
         ul.models { font-size: 0.9em; }\n\
         nav ul { columns: 4 12em; }\n\
         #lightbox { position: fixed; inset: 0; background: rgba(20, 20, 24, 0.97); \
         display: flex; flex-direction: column; align-items: center; justify-content: center; \
         cursor: zoom-out; z-index: 10; }\n\
         #lightbox[hidden] { display: none; }\n\
         #lightbox img { width: min(94vw, 118vh); height: auto; background: #fff; }\n\
         #lightbox p { color: #eee; max-width: 94vw; margin: 0.6em; }\n\
         </style>\n</head>\n<body>\n<h1>subsurf demo gallery</h1>\n\
         <p>Every method of the project on the bundled examples: control meshes, curves and \
         patches. Pictures are drawn by subsurf's own software rasteriser; click one to \
         enlarge it. Pictures that are compared stand side by side with the same camera and, \
         for curvature, the same colour range; the numbers in the captions are measured in \
         this run. Models are OBJ, binary glTF and JSON.</p>\n\
         <nav><ul>\n",
    );
    for (name, _) in sections {
        let _ = writeln!(h, "<li><a href=\"#{0}\">{0}</a></li>", escape(name));
    }
    h.push_str("</ul></nav>\n");
    for (name, groups) in sections {
        let _ = writeln!(h, "<section id=\"{0}\">\n<h2>{0}</h2>", escape(name));
        for (method, items) in groups {
            if items.is_empty() {
                continue;
            }
            let _ = writeln!(h, "<h3>{}</h3>", escape(method));
            let (pictures, models): (Vec<&Item>, Vec<&Item>) = items
                .iter()
                .partition(|i| i.file.ends_with(".png") || i.file.ends_with(".svg"));
            if !pictures.is_empty() {
                h.push_str("<div class=\"grid\">\n");
                for p in pictures {
                    let _ = writeln!(
                        h,
                        "<figure><a href=\"{u}\"><img src=\"{u}\" alt=\"{c}\"></a>\
                         <figcaption>{c}</figcaption></figure>",
                        u = url(&p.file),
                        c = escape(&p.caption)
                    );
                }
                h.push_str("</div>\n");
            }
            if !models.is_empty() {
                h.push_str("<ul class=\"models\">\n");
                for m in models {
                    let counts = m
                        .counts
                        .map(|(v, f)| format!(" ({v} vertices, {f} faces)"))
                        .unwrap_or_default();
                    let _ = writeln!(
                        h,
                        "<li><a href=\"{}\">{}</a>: {}{}</li>",
                        url(&m.file),
                        escape(&m.file),
                        escape(&m.caption),
                        counts
                    );
                }
                h.push_str("</ul>\n");
            }
        }
        h.push_str("</section>\n");
    }
    h.push_str(LIGHTBOX);
    h.push_str("</body>\n</html>\n");
    h
}

/// A click on a picture shows it as large as the window, with its caption; a click or
/// Escape closes it. Without scripts the link opens the picture itself.
const LIGHTBOX: &str =
    "<div id=\"lightbox\" hidden=\"\"><img alt=\"the picture, enlarged\"><p></p></div>
<script>
const box = document.getElementById('lightbox');
for (const a of document.querySelectorAll('figure a')) {
  a.addEventListener('click', (e) => {
    e.preventDefault();
    box.querySelector('img').src = a.getAttribute('href');
    box.querySelector('p').textContent = a.parentElement.querySelector('figcaption').textContent;
    box.hidden = false;
  });
}
box.addEventListener('click', () => { box.hidden = true; });
document.addEventListener('keydown', (e) => { if (e.key === 'Escape') box.hidden = true; });
</script>
";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn examples_are_small_and_tagged() {
        let total: usize = EXAMPLES.iter().map(|e| e.obj.len()).sum();
        assert!(total < 100_000, "bundled examples take {total} bytes");
        for e in EXAMPLES {
            assert!(e.obj.starts_with('#'), "{} has no header comment", e.name);
            assert!(e.rate >= 1);
        }
        assert!(EXAMPLES.iter().any(|e| e.limit));
        for kind in [Kind::Surface, Kind::Knots, Kind::Planar, Kind::Triangles] {
            assert!(EXAMPLES.iter().any(|e| e.kind == kind), "{kind:?}");
        }
        let names: Vec<&str> = EXAMPLES
            .iter()
            .map(|e| e.name)
            .chain(CURVES.iter().map(|c| c.name))
            .chain(PATCHES.iter().map(|p| p.name))
            .collect();
        let unique: std::collections::BTreeSet<&str> = names.iter().copied().collect();
        assert_eq!(
            unique.len(),
            names.len(),
            "section names must differ: {names:?}"
        );
    }

    #[test]
    fn merge_keeps_every_face_with_shifted_vertices() {
        let quad = PolyMesh::from_faces(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            &[[0, 1, 2, 3]],
        )
        .unwrap();
        let tri = PolyMesh::new(
            vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
            vec![0, 3],
            vec![0, 1, 2],
        )
        .unwrap();
        let m = merge([&quad, &tri].into_iter()).unwrap();
        assert_eq!((m.num_vertices(), m.num_faces()), (7, 2));
        assert_eq!(m.face(0), &[0, 1, 2, 3]);
        assert_eq!(m.face(1), &[4, 5, 6]);
        assert_eq!(m.positions()[4], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn the_spline_is_sampled_as_it_evaluates() {
        let cube = parse_obj(EXAMPLES[0].obj.as_bytes(), "cube.obj")
            .unwrap()
            .mesh;
        let spline = QuadSpline::new(&cube).unwrap();
        let s: &dyn limit::Surface = &spline.surface;
        let p = limit::SurfacePoint {
            face: 2,
            subface: 0,
            u: 0.25,
            v: 0.7,
        };
        let a = s.evaluate(p).unwrap();
        let b = spline.surface.eval(2, 0.25, 0.7).unwrap();
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        let bad = limit::SurfacePoint { face: 99, ..p };
        assert!(matches!(
            s.evaluate(bad),
            Err(limit::EvalError::NoSuchFace { face: 99, .. })
        ));
    }

    #[test]
    fn html_escapes_text_and_links() {
        assert_eq!(escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
        assert_eq!(url("cube-c0.25-l3.obj"), "cube-c0.25-l3.obj");
        assert_eq!(url("a b#.png"), "a%20b%23.png");
        let items = vec![
            Item {
                file: "x.png".into(),
                caption: "a <pic>".into(),
                counts: None,
            },
            Item {
                file: "x.obj".into(),
                caption: "a model".into(),
                counts: Some((3, 1)),
            },
        ];
        let page = gallery_html(&[("ex", vec![("M & N", items)])]);
        assert!(
            page.contains("<img src=\"x.png\" alt=\"a &lt;pic&gt;\">"),
            "{page}"
        );
        assert!(page.contains("<a href=\"x.obj\">x.obj</a>: a model (3 vertices, 1 faces)"));
        assert!(page.contains("<h3>M &amp; N</h3>"));
        assert!(page.starts_with("<!DOCTYPE html>") && page.ends_with("</html>\n"));
    }
}
