//! Pictures of a surface: a small, deterministic, headless software rasteriser.
//!
//! [`render`] draws a mesh's exact limit surface (sampled with
//! [`tessellate`](crate::limit::tessellate), normals and curvature from the exact limit
//! derivatives) or a refined control mesh (from [`subdivide`](fn@crate::subdivide)) into an
//! [`RgbImage`], shaded, as reflection lines ([`Paint::Zebra`]), coloured by curvature
//! ([`Paint::Curvature`], with a colour bar), by base face ([`Paint::Faces`]) or with a
//! checker texture through the mesh's texture coordinates ([`Paint::Checker`]), optionally
//! with the control mesh drawn on top.
//!
//! # Pipeline
//! 1. **Scene**: triangles with per-vertex positions, unit normals and (for curvature)
//!    values. On the limit surface every (sub-)face's grid has its own vertices, evaluated
//!    from that face, so that sharp creases keep one normal per side; positions are those of
//!    the watertight tessellation, shared bit for bit, so no pixel falls between triangles.
//! 2. **Camera** (`camera.rs`): an orbit camera around the centre of the bounding box of
//!    what is drawn, at azimuth/elevation [`Render::view`], perspective with a 30° field of
//!    view across the narrower side of the picture, far enough away that the bounding
//!    sphere fits.
//! 3. **Raster** (`raster.rs`): the picture is cut into bands of rows, rendered in parallel.
//!    Each band is sampled [`Render::supersampling`]² times per pixel into a z-buffer that
//!    keeps, per sample, the nearest triangle and its perspective-correct barycentric
//!    coordinates; control mesh lines (`lines.rs`) are then drawn into the band, depth-tested.
//! 4. **Shading** (`shade.rs`, `zebra.rs`, `curvature.rs`) per sample from the interpolated
//!    normal, then a box filter down to pixels, and the colour bar (`colorbar.rs`).
//!
//! Output is deterministic: the same input and options give the same bytes, whatever the
//! number of threads (every band is computed independently, triangles in a fixed order,
//! depth ties going to the earlier triangle).
//!
//! ```
//! use subsurf::mesh::{Options, PolyMesh};
//! use subsurf::render::{render, Paint, Render};
//! let p = vec![
//!     [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
//!     [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
//! ];
//! let f = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
//! let cube = PolyMesh::from_faces(p, &f).unwrap();
//! let opts = Render { width: 160, height: 120, paint: Paint::Zebra, ..Render::default() };
//! let img = render(&cube, &Options::default(), &opts).unwrap();
//! assert_eq!((img.width(), img.height()), (160, 120));
//! ```

mod camera;
mod colorbar;
pub(crate) mod curvature;
mod font;
mod lines;
mod raster;
mod scene;
mod shade;
mod zebra;

use std::io::{self, Write};

pub use curvature::{sample_curvature, Curvature, CurvatureKind, CurvatureSample};
pub use image::RgbImage;

use crate::io::Up;
use crate::limit::{BuildError, EvalError, FaceVaryingError, TessellateError};
use crate::mesh::{MeshError, Options, PolyMesh};
use crate::scheme::Scheme;
use camera::{Camera, Viewport};
use rayon::prelude::*;
use scene::Scene;

/// Which surface to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// The exact limit surface of [`Render::scheme`], sampled `rate × rate` per quad face
    /// (`rate²` triangles per triangle of a Loop surface; see
    /// [`tessellate`](crate::limit::tessellate)), with exact limit normals.
    Limit {
        /// Samples per base edge (at least 1).
        rate: u32,
    },
    /// The control mesh refined this many levels with [`Render::scheme`] (0: the input
    /// itself), with normals averaged from its faces.
    Level(u32),
}

/// How normals vary over the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Shading {
    /// Per-pixel normals interpolated from the vertices (exact limit normals, or face
    /// normals averaged at the vertices of a refined mesh).
    #[default]
    Smooth,
    /// One normal per drawn polygon (a tessellation quad, or a refined face).
    Flat,
}

/// What colours the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Paint {
    /// A neutral clay colour, lit by a key and a fill light.
    #[default]
    Plain,
    /// Base faces in alternating colours (shows the patches): a greedy colouring in face
    /// order, so that faces sharing an edge differ — a checkerboard on a grid of quads
    /// numbered by rows, three colours on a cube.
    Faces,
    /// Reflection lines: black and white stripes of an environment of parallel light
    /// planes, reflected per sample by the interpolated normal (see `zebra.rs`). A kink
    /// (normal discontinuity) breaks the stripes; a curvature jump kinks them.
    Zebra,
    /// Curvature of the exact limit surface ([`Geometry::Limit`] only), with a colour bar.
    Curvature(CurvatureKind),
    /// A checkerboard texture of `squares × squares` squares over the unit square of
    /// texture coordinates, mapped through the mesh's face-varying channel named `"uv"`
    /// (OBJ `vt`): on the limit surface their exact limit in the mode of
    /// [`Options::face_varying`] ([`FaceVaryingSurface`](crate::limit::FaceVaryingSurface),
    /// each (sub-)face's samples from that face, so seams stay sharp), on a refined level
    /// the refined values, interpolated per pixel. Squares outside the unit square are
    /// tinted red, so that texture coordinates beyond the image show; stretching, seams
    /// and distortion of the mapping show as uneven or broken squares.
    Checker {
        /// Squares along each side of the unit square (1 to 1024).
        squares: u32,
    },
}

/// Options of [`render`].
#[derive(Clone, Debug, PartialEq)]
pub struct Render {
    /// Picture width in pixels (16 to 8192).
    pub width: u32,
    /// Picture height in pixels (16 to 8192).
    pub height: u32,
    /// Samples per pixel along each axis (1 to 8); the picture is box-filtered down.
    pub supersampling: u32,
    /// Which surface.
    pub geometry: Geometry,
    /// Smooth or flat normals.
    pub shading: Shading,
    /// Colouring.
    pub paint: Paint,
    /// Draw the input control mesh's edges on top: dark where they are in front of the
    /// surface (depth-tested with a bias of 0.5 % of the distance, so that lines lying on
    /// the surface show), faint where the surface hides them.
    pub control_mesh: bool,
    /// Camera azimuth and elevation in degrees: azimuth turns counter-clockwise around the
    /// up axis seen from above, elevation looks down from above (negative: from below).
    pub view: (f64, f64),
    /// Which axis is up.
    pub up: Up,
    /// Magnification of the fitted view (1: the bounding sphere fits; 4: a quarter of it
    /// around the centre of the picture, to look closely at the middle of the view).
    pub zoom: f64,
    /// Fixed curvature colour range `(min, max)`; `None`: robust automatic range (see
    /// `curvature::robust_range`).
    pub curvature_range: Option<(f64, f64)>,
    /// Background colour.
    pub background: [u8; 3],
    /// The subdivision scheme whose limit surface ([`Geometry::Limit`]) or refined levels
    /// ([`Geometry::Level`]) are drawn: Catmull-Clark (the default), Loop (every face a
    /// triangle: [`LoopSurface`](crate::limit::LoopSurface)) or bilinear
    /// ([`BilinearSurface`](crate::limit::BilinearSurface)); the adjustable scheme's refined
    /// levels. Other limit surfaces (the adjustable scheme's
    /// [`MixedSurface`](crate::MixedSurface), NURSS) are drawn with [`render_surface`];
    /// NURSS levels are not drawn ([`RenderError::Scheme`]).
    pub scheme: Scheme,
    /// Bytes the exact limit surface ([`Geometry::Limit`]) may take, built and evaluated at
    /// the rate (see [`LimitSurface::new_within`](crate::limit::LimitSurface::new_within)
    /// and [`LimitSurface::estimate_memory`](crate::limit::LimitSurface::estimate_memory)):
    /// over it, [`RenderError::Build`] or [`RenderError::SurfaceMemory`] before a point is
    /// evaluated. `None`: no limit.
    pub surface_memory: Option<u64>,
}

impl Default for Render {
    fn default() -> Self {
        Self {
            width: 800,
            height: 600,
            supersampling: 4,
            geometry: Geometry::Limit { rate: 16 },
            shading: Shading::Smooth,
            paint: Paint::Plain,
            control_mesh: false,
            view: (30.0, 20.0),
            up: Up::Z,
            zoom: 1.0,
            curvature_range: None,
            background: [244, 244, 246],
            scheme: Scheme::CatmullClark,
            surface_memory: None,
        }
    }
}

/// Errors of [`render`].
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The picture size is out of range.
    #[error("picture size {width}x{height} is out of range (each side 16 to 8192 pixels)")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// The supersampling factor is out of range.
    #[error("supersampling {0} is out of range (1 to 8)")]
    BadSupersampling(u32),
    /// The view angles are not finite.
    #[error("view angles ({0}, {1}) are not finite")]
    BadView(f64, f64),
    /// The zoom factor is out of range.
    #[error("zoom {0} is out of range (0.01 to 1000)")]
    BadZoom(f64),
    /// Curvature needs the exact limit surface.
    #[error("curvature is computed on the exact limit surface: render the limit, not a level")]
    CurvatureNeedsLimit,
    /// The fixed curvature range is empty or not finite.
    #[error("curvature range {0}..{1} is empty or not finite")]
    BadRange(f64, f64),
    /// The scheme ([`Render::scheme`]) cannot be drawn this way.
    #[error("the {scheme} scheme cannot be drawn as {what} (see Render::scheme)")]
    Scheme {
        /// The scheme's name.
        scheme: &'static str,
        /// What was asked: "a limit surface" or "a refined level".
        what: &'static str,
    },
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Sampling the limit surface failed.
    #[error(transparent)]
    Tessellate(#[from] TessellateError),
    /// Evaluating the limit surface failed (not expected for a surface of this mesh).
    #[error(transparent)]
    Eval(#[from] EvalError),
    /// Too many polygons to draw.
    #[error("drawing this would take about {faces} polygons, more than {limit}: use a lower rate or level")]
    TooLarge {
        /// Estimated polygons.
        faces: u128,
        /// The limit.
        limit: u64,
    },
    /// Building the limit surface stopped at [`Render::surface_memory`].
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Evaluating the limit surface at the rate would take more than
    /// [`Render::surface_memory`].
    #[error(
        "the limit surface evaluated at rate {rate} needs about {} MiB, more than the limit \
         of {} MiB: use a lower rate",
        estimate.div_ceil(1 << 20),
        limit >> 20
    )]
    SurfaceMemory {
        /// The rate.
        rate: u32,
        /// Estimated bytes.
        estimate: u64,
        /// Allowed bytes.
        limit: u64,
    },
    /// [`Paint::Checker`] on a mesh without texture coordinates.
    #[error("the mesh has no texture coordinates (vt) to map a texture with")]
    NoTextureCoordinates,
    /// [`Paint::Checker`] with another surface than the mesh's limit or a level.
    #[error("a texture is drawn on the mesh's limit surface or a refined level only")]
    TextureNeedsMeshSurface,
    /// [`Paint::Checker`] with a number of squares out of range.
    #[error("checker squares {0} out of range (1 to 1024)")]
    BadSquares(u32),
    /// Evaluating the texture coordinates' limit failed.
    #[error("texture coordinates: {0}")]
    FaceVarying(#[from] FaceVaryingError),
    /// There is nothing to draw (no faces, or every face is a hole).
    #[error("nothing to draw: the mesh has no faces with a surface")]
    Empty,
}

/// A picture and what was used to draw it.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The picture.
    pub image: RgbImage,
    /// Triangles drawn.
    pub triangles: usize,
    /// The curvature colour range `(min, max)`, with [`Paint::Curvature`].
    pub curvature_range: Option<(f64, f64)>,
}

/// Renders `mesh` (subdivided with scheme `options`) as `opts` asks. See the module docs.
///
/// # Errors
/// [`RenderError`]: bad options, an invalid mesh, nothing to draw.
pub fn render(mesh: &PolyMesh, options: &Options, opts: &Render) -> Result<RgbImage, RenderError> {
    render_detailed(mesh, options, opts).map(|r| r.image)
}

/// [`render`], also returning the triangle count and the curvature range used.
///
/// # Errors
/// As [`render`].
pub fn render_detailed(
    mesh: &PolyMesh,
    options: &Options,
    opts: &Render,
) -> Result<Rendered, RenderError> {
    render_surface(mesh, options, opts, None)
}

/// [`render_detailed`], drawing `surface` (sampled on the limit surface's grid, see
/// [`Geometry::Limit`]) instead of the limit surface of `mesh` when given.
///
/// # Errors
/// As [`render`].
pub fn render_surface(
    mesh: &PolyMesh,
    options: &Options,
    opts: &Render,
    surface: Option<&dyn crate::limit::Surface>,
) -> Result<Rendered, RenderError> {
    check(opts)?;
    if surface.is_some() && matches!(opts.paint, Paint::Checker { .. }) {
        return Err(RenderError::TextureNeedsMeshSurface);
    }
    let scene = match surface {
        Some(_) => Scene::build_with(mesh, options, opts, surface)?,
        None => Scene::build(mesh, options, opts)?,
    };
    if scene.triangles.is_empty() {
        return Err(RenderError::Empty);
    }
    let (w, h) = (opts.width as usize, opts.height as usize);
    let ss = opts.supersampling as usize;

    // The colour bar takes a strip on the right; the surface is framed in the rest.
    let bar = match (opts.paint, &scene.values) {
        (Paint::Curvature(kind), Some(values)) => {
            let range = match opts.curvature_range {
                Some(r) => r,
                None => curvature::robust_range(values, kind),
            };
            Some(colorbar::ColorBar::layout(kind, range, w, h))
        }
        _ => None,
    };
    let strip = bar.as_ref().map_or(0, |b| b.strip_width);
    let viewport = Viewport {
        width: (w - strip) as f64,
        height: h as f64,
    };
    let (centre, radius) = scene.bounding_sphere(opts.control_mesh);
    let camera = Camera::orbit(centre, radius, opts.view, opts.up, viewport, opts.zoom);
    let frame = scene.project(&camera, ss as f64);

    let lines = if opts.control_mesh {
        scene
            .edges
            .iter()
            .filter_map(|&[a, b]| {
                Some([
                    camera.project(&a, ss as f64)?,
                    camera.project(&b, ss as f64)?,
                ])
            })
            .collect()
    } else {
        Vec::new()
    };

    let band_rows = 8usize;
    let bands = h.div_ceil(band_rows);
    let tri_bins = raster::bin_triangles(&frame, &scene.triangles, band_rows * ss, bands);
    let line_bins = lines::bin_lines(&lines, band_rows * ss, bands, lines::half_width(ss));
    let range = bar.as_ref().map(|b| b.range);
    let shader = shade::Shader::new(opts, &scene, &frame, range);

    let rows: Vec<Vec<u8>> = (0..bands)
        .into_par_iter()
        .map(|b| {
            let y0 = b * band_rows;
            let rows = band_rows.min(h - y0);
            let mut band = raster::Band::new(w * ss, y0 * ss, rows * ss);
            for &t in &tri_bins[b] {
                band.triangle(t, &frame.screen, &scene.triangles[t as usize]);
            }
            let cover = lines::draw(&band, &lines, &line_bins[b], ss);
            shader.resolve(&band, &cover, ss, w, rows)
        })
        .collect();
    let image = compose(opts, rows, bar.as_ref());
    Ok(Rendered {
        image,
        triangles: scene.triangles.len(),
        curvature_range: range,
    })
}

/// The picture of `opts`'s size from its bands of RGB rows, with the colour bar `bar` drawn
/// in its strip on the right. The surface is framed left of the strip, but a zoomed view
/// runs past it: the strip is cleared so that the bar never lies over the surface.
fn compose(opts: &Render, bands: Vec<Vec<u8>>, bar: Option<&colorbar::ColorBar>) -> RgbImage {
    let w = opts.width as usize;
    let mut image = RgbImage::new(opts.width, opts.height);
    let mut y = 0u32;
    for band in bands {
        for row in band.chunks_exact(w * 3) {
            for (x, px) in row.chunks_exact(3).enumerate() {
                image.put_pixel(x as u32, y, image::Rgb([px[0], px[1], px[2]]));
            }
            y += 1;
        }
    }
    if let Some(bar) = bar {
        let x0 = (w - bar.strip_width) as u32;
        for y in 0..opts.height {
            for x in x0..opts.width {
                image.put_pixel(x, y, image::Rgb(opts.background));
            }
        }
        bar.draw(&mut image);
    }
    image
}

fn check(opts: &Render) -> Result<(), RenderError> {
    let side = 16..=8192;
    if !side.contains(&opts.width) || !side.contains(&opts.height) {
        return Err(RenderError::BadSize {
            width: opts.width,
            height: opts.height,
        });
    }
    if !(1..=8).contains(&opts.supersampling) {
        return Err(RenderError::BadSupersampling(opts.supersampling));
    }
    if !opts.view.0.is_finite() || !opts.view.1.is_finite() {
        return Err(RenderError::BadView(opts.view.0, opts.view.1));
    }
    if !(opts.zoom.is_finite() && (0.01..=1000.0).contains(&opts.zoom)) {
        return Err(RenderError::BadZoom(opts.zoom));
    }
    if let Some((lo, hi)) = opts.curvature_range {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(RenderError::BadRange(lo, hi));
        }
    }
    if matches!(opts.paint, Paint::Curvature(_)) && matches!(opts.geometry, Geometry::Level(_)) {
        return Err(RenderError::CurvatureNeedsLimit);
    }
    if let Paint::Checker { squares } = opts.paint {
        if !(1..=1024).contains(&squares) {
            return Err(RenderError::BadSquares(squares));
        }
    }
    Ok(())
}

/// Writes `image` as PNG (8-bit RGB; deterministic bytes).
///
/// The PNG is encoded in memory (smaller than the image) and written in one call, so that
/// the errors of `w` reach the caller as they are: the encoder would turn them into text,
/// and a closed pipe would no longer read as [`io::ErrorKind::BrokenPipe`].
///
/// # Errors
/// Errors of `w`, and encoder errors as [`io::ErrorKind::Other`].
pub fn write_png<W: Write>(mut w: W, image: &RgbImage) -> io::Result<()> {
    use image::ImageEncoder;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(
            image.as_raw(),
            image.width(),
            image.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(io::Error::other)?;
    w.write_all(&png)
}
