//! The software renderer: pictures of the limit surface are where they should be, have the
//! expected symmetry, stripes and colours, are deterministic, and curvature has the right
//! signs (checked on the per-vertex values, not on pixels).

use subsurf::io::parse_obj;
use subsurf::mesh::{Options, PolyMesh};
use subsurf::render::{
    render, render_detailed, write_png, Geometry, Paint, Render, RenderError, RgbImage, Shading,
};
use subsurf::render::{sample_curvature, CurvatureKind};
use subsurf::Scheme;

use crate::common::cube;

fn example(name: &str) -> (PolyMesh, Options) {
    let path = format!(
        "{}/../../examples/meshes/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    let bytes = std::fs::read(&path).unwrap();
    let obj = parse_obj(&bytes, &path).unwrap();
    let options = obj.options.resolve(Options::default());
    (obj.mesh, options)
}

fn small(paint: Paint) -> Render {
    Render {
        width: 160,
        height: 120,
        paint,
        ..Render::default()
    }
}

/// `mesh` with every quad `a b c d` split into the triangles `a b c` and `a c d` (texture
/// coordinates too): on a grid of quads, a Loop mesh whose interior vertices are regular
/// (valence 6).
fn triangulated(mesh: &PolyMesh) -> PolyMesh {
    use subsurf::mesh::FaceVarying;
    let split = |f: &[u32]| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]];
    let faces: Vec<[u32; 3]> = mesh.faces().flat_map(split).collect();
    let mut out = PolyMesh::from_faces(mesh.positions().to_vec(), &faces).unwrap();
    for c in &mesh.face_varying {
        let offsets = mesh.face_offsets();
        let indices: Vec<u32> = (0..mesh.num_faces())
            .flat_map(|f| split(&c.indices()[offsets[f] as usize..offsets[f + 1] as usize]))
            .flatten()
            .collect();
        let values = c.values().to_vec();
        out.face_varying
            .push(FaceVarying::new(c.name(), c.dim(), values, indices).unwrap());
    }
    out
}

/// Pixels that differ from the background.
fn mask(img: &RgbImage, background: [u8; 3]) -> Vec<bool> {
    img.pixels().map(|p| p.0 != background).collect()
}

fn luminance(p: &image::Rgb<u8>) -> f64 {
    0.2126 * f64::from(p.0[0]) + 0.7152 * f64::from(p.0[1]) + 0.0722 * f64::from(p.0[2])
}

#[test]
fn the_cube_fills_the_middle_of_the_picture() {
    let opts = small(Paint::Plain);
    let img = render(&cube(), &Options::default(), &opts).unwrap();
    assert_eq!((img.width(), img.height()), (160, 120));
    let m = mask(&img, opts.background);
    let count = m.iter().filter(|&&x| x).count();
    // A sphere-like blob fitted to the shorter side: a good part of the picture, not all.
    assert!(
        count > 160 * 120 / 5 && count < 160 * 120 * 3 / 4,
        "{count}"
    );
    let (mut cx, mut cy) = (0.0, 0.0);
    for (i, _) in m.iter().enumerate().filter(|(_, &x)| x) {
        cx += (i % 160) as f64;
        cy += (i / 160) as f64;
    }
    let (cx, cy) = (cx / count as f64, cy / count as f64);
    assert!(
        (cx - 79.5).abs() < 4.0 && (cy - 59.5).abs() < 4.0,
        "({cx}, {cy})"
    );
    // The corners of the picture are background; shading varies across the surface.
    assert!(!m[0] && !m[159] && !m[119 * 160] && !m[120 * 160 - 1]);
    let lum: Vec<f64> = img
        .pixels()
        .zip(&m)
        .filter(|(_, &x)| x)
        .map(|(p, _)| luminance(p))
        .collect();
    let (lo, hi) = lum
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(hi - lo > 60.0, "{lo}..{hi}");
}

#[test]
fn lit_from_the_upper_left() {
    // Front view: the key light is above and to the left, so the upper-left quarter of the
    // surface is brighter than the lower-right one (the shading is not inverted).
    let opts = Render {
        view: (0.0, 0.0),
        ..small(Paint::Plain)
    };
    let img = render(&cube(), &Options::default(), &opts).unwrap();
    let m = mask(&img, opts.background);
    let mean = |x0: u32, y0: u32| {
        let mut s = (0.0, 0);
        for y in y0..y0 + 60 {
            for x in x0..x0 + 80 {
                if m[(y * 160 + x) as usize] {
                    s.0 += luminance(img.get_pixel(x, y));
                    s.1 += 1;
                }
            }
        }
        s.0 / f64::from(s.1)
    };
    assert!(mean(0, 0) > mean(80, 60) + 20.0);
}

#[test]
fn a_symmetric_view_gives_a_symmetric_silhouette() {
    // Looking at the middle of a face: the cube's limit surface is mirror-symmetric left to
    // right and top to bottom in the picture.
    let opts = Render {
        view: (0.0, 0.0),
        width: 161,
        height: 121,
        ..small(Paint::Plain)
    };
    let img = render(&cube(), &Options::default(), &opts).unwrap();
    let m = mask(&img, opts.background);
    let (w, h) = (161usize, 121usize);
    let (mut lr, mut tb, mut total) = (0, 0, 0);
    for y in 0..h {
        for x in 0..w {
            let here = m[y * w + x];
            total += usize::from(here);
            lr += usize::from(here != m[y * w + (w - 1 - x)]);
            tb += usize::from(here != m[(h - 1 - y) * w + x]);
        }
    }
    assert!(total > 1000);
    // Anti-aliased edge pixels may differ by a shade, not by coverage.
    assert!(lr * 200 < total, "{lr} of {total} differ left-right");
    assert!(tb * 200 < total, "{tb} of {total} differ top-bottom");
}

#[test]
fn zebra_has_dark_and_light_stripes() {
    let opts = small(Paint::Zebra);
    let img = render(&cube(), &Options::default(), &opts).unwrap();
    let m = mask(&img, opts.background);
    let lum: Vec<f64> = img
        .pixels()
        .zip(&m)
        .filter(|(_, &x)| x)
        .map(|(p, _)| luminance(p))
        .collect();
    let dark = lum.iter().filter(|&&l| l < 60.0).count();
    let light = lum.iter().filter(|&&l| l > 200.0).count();
    assert!(dark * 8 > lum.len(), "{dark} dark of {}", lum.len());
    assert!(light * 8 > lum.len(), "{light} light of {}", lum.len());
    // Stripes are grey-scale (edge pixels mix in the slightly bluish background).
    assert!(img.pixels().all(|p| {
        let [r, g, b] = p.0;
        r.abs_diff(g) <= 1 && g.abs_diff(b) <= 2
    }));
}

#[test]
fn renders_are_deterministic() {
    for paint in [
        Paint::Plain,
        Paint::Zebra,
        Paint::Faces,
        Paint::Curvature(CurvatureKind::Mean),
    ] {
        let opts = Render {
            control_mesh: true,
            ..small(paint)
        };
        let png = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let img = pool
                .install(|| render(&cube(), &Options::default(), &opts))
                .unwrap();
            let mut bytes = Vec::new();
            write_png(&mut bytes, &img).unwrap();
            bytes
        };
        let a = png(1);
        assert_eq!(&a[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(a, png(1), "{paint:?}");
        assert_eq!(a, png(3), "{paint:?}");
    }
}

#[test]
fn torus_gaussian_curvature_is_positive_outside_and_negative_inside() {
    // Major radius 1, minor 0.4, axis z.
    let (mesh, options) = example("torus.obj");
    let samples = sample_curvature(&mesh, &options, Scheme::CatmullClark, 6).unwrap();
    let (mut outside, mut inside) = (0, 0);
    for s in &samples {
        let c = s
            .curvature
            .expect("a torus of quads of valence 4 is C2 everywhere");
        let rho = s.position[0].hypot(s.position[1]);
        if rho > 1.15 {
            assert!(c.gauss > 0.0, "K = {} at {:?}", c.gauss, s.position);
            outside += 1;
        } else if rho < 0.85 {
            assert!(c.gauss < 0.0, "K = {} at {:?}", c.gauss, s.position);
            inside += 1;
        }
        // The torus is convex along its tube: the mean curvature is positive everywhere.
        assert!(c.mean > 0.0, "H = {} at {:?}", c.mean, s.position);
        assert!(c.max >= c.mean.abs());
    }
    assert!(outside > 100 && inside > 100, "{outside} {inside}");
}

/// The Loop limit of the torus split into triangles (every vertex regular: quartic box
/// splines, C2) has the torus's curvature signs everywhere, at every point of its
/// triangular grids.
#[test]
fn loop_torus_curvature_has_the_signs_of_a_torus() {
    let (mesh, options) = example("torus.obj");
    let tri = triangulated(&mesh);
    let samples = sample_curvature(&tri, &options, Scheme::Loop, 4).unwrap();
    // (4 + 1)(4 + 2) / 2 points per triangle.
    assert_eq!(samples.len(), tri.num_faces() * 15);
    let (mut outside, mut inside) = (0, 0);
    for s in &samples {
        let c = s
            .curvature
            .expect("a regular Loop surface is C2 everywhere");
        let rho = s.position[0].hypot(s.position[1]);
        if rho > 1.15 {
            assert!(c.gauss > 0.0, "K = {} at {:?}", c.gauss, s.position);
            outside += 1;
        } else if rho < 0.85 {
            assert!(c.gauss < 0.0, "K = {} at {:?}", c.gauss, s.position);
            inside += 1;
        }
        assert!(c.mean > 0.0, "H = {} at {:?}", c.mean, s.position);
    }
    assert!(outside > 100 && inside > 100, "{outside} {inside}");
}

#[test]
fn cube_limit_is_convex_and_curvature_is_missing_only_at_its_corners() {
    let samples = sample_curvature(&cube(), &Options::default(), Scheme::CatmullClark, 4).unwrap();
    let mut missing = 0;
    for s in &samples {
        match s.curvature {
            Some(c) => {
                assert!(c.gauss > 0.0 && c.mean > 0.0, "{c:?} at {:?}", s.position);
                // Outward normal.
                let d: f64 = (0..3).map(|k| s.normal[k] * (s.position[k] - 0.5)).sum();
                assert!(d > 0.0);
            }
            None => {
                missing += 1;
                let u_end = s.point.u == 0.0 || s.point.u == 1.0;
                let v_end = s.point.v == 0.0 || s.point.v == 1.0;
                assert!(u_end && v_end, "{:?}", s.point);
            }
        }
    }
    // Each face's grid meets 4 extraordinary corners.
    assert_eq!(missing, 6 * 4);
}

#[test]
fn curvature_pictures_have_a_colour_bar() {
    let opts = Render {
        width: 320,
        height: 240,
        ..small(Paint::Curvature(CurvatureKind::Gauss))
    };
    let r = render_detailed(&cube(), &Options::default(), &opts).unwrap();
    let (lo, hi) = r.curvature_range.unwrap();
    assert!(lo < 0.0 && hi > 0.0 && (lo + hi).abs() < 1e-12);
    // The bar's column: red at the top, blue at the bottom, somewhere in the right strip.
    let img = &r.image;
    let redish = |p: &image::Rgb<u8>| p.0[0] > 150 && p.0[2] < 100;
    let blueish = |p: &image::Rgb<u8>| p.0[2] > 150 && p.0[0] < 100;
    let column = (240..320).find(|&x| (0..240).any(|y| redish(img.get_pixel(x, y))));
    let x = column.expect("a red bar on the right");
    assert!((0..240).any(|y| blueish(img.get_pixel(x, y))));
    // The surface itself (convex) is red, never blue.
    assert!((0..200).all(|x| (0..240).all(|y| !blueish(img.get_pixel(x, y)))));
}

#[test]
fn a_zoomed_surface_does_not_run_under_the_colour_bar() {
    // Zoomed in three times, the cube's surface fills the picture; the colour bar's strip
    // on the right stays background but for the bar and its labels, and the strip's margin
    // right of the text (the last columns) is background from top to bottom.
    let opts = Render {
        width: 320,
        height: 240,
        zoom: 3.0,
        ..small(Paint::Curvature(CurvatureKind::Gauss))
    };
    let img = render(&cube(), &Options::default(), &opts).unwrap();
    let bg = image::Rgb(opts.background);
    assert_ne!(*img.get_pixel(100, 120), bg, "the surface fills the middle");
    for x in 316..320 {
        for y in 0..240 {
            assert_eq!(*img.get_pixel(x, y), bg, "pixel ({x}, {y})");
        }
    }
}

#[test]
fn faces_levels_flat_shading_and_the_control_mesh_change_the_picture() {
    let o = Options::default();
    let base = render(&cube(), &o, &small(Paint::Plain)).unwrap();
    let faces = render(&cube(), &o, &small(Paint::Faces)).unwrap();
    assert_ne!(base, faces);
    // Neighbouring faces differ: at least three hues are visible on a cube.
    let mut hues: Vec<[u8; 3]> = faces
        .pixels()
        .map(|p| p.0.map(|c| c / 64))
        .filter(|c| c[0] != c[2])
        .collect();
    hues.sort_unstable();
    hues.dedup();
    assert!(hues.len() >= 3, "{hues:?}");
    let level = Render {
        geometry: Geometry::Level(1),
        shading: Shading::Flat,
        ..small(Paint::Plain)
    };
    let l1 = render(&cube(), &o, &level).unwrap();
    assert_ne!(base, l1);
    let cage = Render {
        control_mesh: true,
        ..small(Paint::Plain)
    };
    let with_lines = render(&cube(), &o, &cage).unwrap();
    // Dark bluish line pixels (the clay surface is warm: red above blue).
    let lines = |img: &RgbImage| {
        img.pixels()
            .filter(|p| p.0[2] >= p.0[0] && luminance(p) < 120.0)
            .count()
    };
    assert_eq!(lines(&base), 0);
    assert!(lines(&with_lines) > 200, "{}", lines(&with_lines));
}

/// With `Render::scheme` Loop, the limit surface is drawn as `rate²` triangles per
/// triangle and a level as four triangles per triangle per level; zebra, curvature and
/// base faces are drawn on them, and the picture differs from Catmull-Clark's of the same
/// triangles.
#[test]
fn loop_surfaces_and_levels_are_drawn_as_triangles() {
    let (mesh, options) = example("torus.obj");
    let tri = triangulated(&mesh);
    let draw = |geometry, paint| {
        let opts = Render {
            geometry,
            scheme: Scheme::Loop,
            ..small(paint)
        };
        render_detailed(&tri, &options, &opts).unwrap()
    };
    let limit = Geometry::Limit { rate: 4 };
    let zebra = draw(limit, Paint::Zebra);
    assert_eq!(zebra.triangles, tri.num_faces() * 16);
    let lum: Vec<f64> = zebra.image.pixels().map(luminance).collect();
    assert!(lum.iter().any(|&l| l < 40.0) && lum.iter().any(|&l| l > 215.0));
    let curvature = draw(limit, Paint::Curvature(CurvatureKind::Gauss));
    let (lo, hi) = curvature.curvature_range.unwrap();
    assert!(lo < 0.0 && hi > 0.0, "{lo}..{hi}");
    let level = draw(Geometry::Level(2), Paint::Faces);
    assert_eq!(level.triangles, tri.num_faces() * 16);
    let cc = Render {
        geometry: limit,
        ..small(Paint::Zebra)
    };
    assert_ne!(render(&tri, &options, &cc).unwrap(), zebra.image);
}

/// The bilinear limit surface of the cube is the cube itself: flat faces, zero curvature at
/// every sample (none at the grids' corners, where zero second derivatives are read as a
/// corner's), normals along the faces' normals; drawn, it differs from Catmull-Clark's.
#[test]
fn the_bilinear_cube_is_flat() {
    let o = Options::default();
    let samples = sample_curvature(&cube(), &o, Scheme::Bilinear, 4).unwrap();
    assert_eq!(samples.len(), 6 * 25);
    for s in &samples {
        let corner = [s.point.u, s.point.v].iter().all(|&x| x == 0.0 || x == 1.0);
        let Some(c) = s.curvature else {
            assert!(corner, "{:?}", s.point);
            continue;
        };
        assert!(c.gauss == 0.0 && c.mean == 0.0 && c.max == 0.0, "{c:?}");
        let p = s.position;
        let on_face = (0..3).any(|k| (p[k] == 0.0 || p[k] == 1.0) && s.normal[k].abs() == 1.0);
        assert!(on_face, "{:?} {:?}", p, s.normal);
    }
    let opts = Render {
        scheme: Scheme::Bilinear,
        ..small(Paint::Plain)
    };
    let bilinear = render(&cube(), &o, &opts).unwrap();
    assert_ne!(bilinear, render(&cube(), &o, &small(Paint::Plain)).unwrap());
}

#[test]
fn loop_needs_triangles_and_nurss_levels_are_refused() {
    let o = Options::default();
    let opts = Render {
        scheme: Scheme::Loop,
        ..small(Paint::Plain)
    };
    let e = render(&cube(), &o, &opts).unwrap_err();
    assert!(e.to_string().contains("face 0 has 4 vertices"), "{e}");
    for geometry in [Geometry::Level(1), Geometry::Limit { rate: 2 }] {
        let opts = Render {
            scheme: Scheme::Nurss,
            geometry,
            ..small(Paint::Plain)
        };
        let e = render(&cube(), &o, &opts).unwrap_err();
        assert!(matches!(e, RenderError::Scheme { .. }), "{e}");
    }
}

#[test]
fn holes_are_not_drawn() {
    let o = Options::default();
    let opts = Render {
        view: (0.0, 89.0),
        ..small(Paint::Plain)
    };
    let closed = render(&cube(), &o, &opts).unwrap();
    let mut open = cube();
    open.tags.holes = vec![1]; // the top face, seen from above
    let holed = render(&open, &o, &opts).unwrap();
    assert_ne!(closed, holed);
    // Inside, the back faces are lit (two-sided), not black.
    let m = mask(&holed, opts.background);
    let centre = holed.get_pixel(80, 60);
    assert!(m[60 * 160 + 80] && luminance(centre) > 30.0);
    open.tags.holes = (0..6).collect();
    assert!(matches!(render(&open, &o, &opts), Err(RenderError::Empty)));
}

#[test]
fn bad_options_are_errors() {
    let o = Options::default();
    let bad = |opts: Render| render(&cube(), &o, &opts).unwrap_err();
    assert!(matches!(
        bad(Render {
            width: 4,
            ..Render::default()
        }),
        RenderError::BadSize { .. }
    ));
    assert!(matches!(
        bad(Render {
            geometry: Geometry::Level(1),
            paint: Paint::Curvature(CurvatureKind::Mean),
            ..Render::default()
        }),
        RenderError::CurvatureNeedsLimit
    ));
    assert!(matches!(
        bad(Render {
            geometry: Geometry::Limit { rate: 0 },
            ..Render::default()
        }),
        RenderError::Tessellate(_)
    ));
    assert!(matches!(
        bad(Render {
            geometry: Geometry::Limit { rate: 2000 },
            ..Render::default()
        }),
        RenderError::TooLarge { .. }
    ));
    assert!(matches!(
        bad(Render {
            view: (f64::NAN, 0.0),
            ..Render::default()
        }),
        RenderError::BadView(..)
    ));
    assert!(matches!(
        bad(Render {
            curvature_range: Some((1.0, 1.0)),
            ..Render::default()
        }),
        RenderError::BadRange(..)
    ));
}

/// With `surface_memory`, the limit surface is held to it: the build stops below its
/// configurations, the evaluation is refused below the estimate at the rate, and at the
/// estimate the picture is the one drawn without a limit.
#[test]
fn the_limit_surface_is_held_to_its_memory() {
    use subsurf::limit::{BuildError, LimitSurface};
    let mesh = cube();
    let options = Options::default();
    let opts = |surface_memory| Render {
        geometry: Geometry::Limit { rate: 64 },
        surface_memory,
        ..small(Paint::Plain)
    };
    let built = LimitSurface::estimate_build_memory(&mesh);
    assert!(matches!(
        render(&mesh, &options, &opts(Some(built))),
        Err(RenderError::Build(BuildError::TooLarge { .. }))
    ));
    let estimate = LimitSurface::new(&mesh, options)
        .unwrap()
        .estimate_memory(64);
    match render(&mesh, &options, &opts(Some(estimate - 1))) {
        Err(RenderError::SurfaceMemory {
            rate: 64,
            estimate: e,
            limit,
        }) => assert_eq!((e, limit), (estimate, estimate - 1)),
        other => panic!("not refused: {:?}", other.map(|i| i.dimensions())),
    }
    let held = render(&mesh, &options, &opts(Some(estimate))).unwrap();
    assert_eq!(held, render(&mesh, &options, &opts(None)).unwrap());
}

/// Two unit quads side by side in the plane `z = 0`, each mapping the whole unit square of
/// texture coordinates: a seam along their shared edge, where the left quad has `s = 1`
/// and the right one `s = 0`.
fn two_textured_quads() -> PolyMesh {
    use subsurf::mesh::FaceVarying;
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
    ];
    let mut m = PolyMesh::from_faces(p, &[[0u32, 1, 4, 3], [1, 2, 5, 4]]).unwrap();
    let uv = vec![0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0];
    m.face_varying
        .push(FaceVarying::new("uv", 2, uv, vec![0, 1, 2, 3, 0, 1, 2, 3]).unwrap());
    m
}

/// The runs of light and dark surface pixels along row `y`, of at least 3 pixels
/// (background skipped, and the edge pixels that blend a square with the background or
/// with another square).
fn checker_runs(img: &RgbImage, y: u32, background: [u8; 3]) -> Vec<bool> {
    let mut runs: Vec<(bool, u32)> = Vec::new();
    for x in 0..img.width() {
        let p = img.get_pixel(x, y);
        if p.0 == background {
            continue;
        }
        let light = luminance(p) > 128.0;
        match runs.last_mut() {
            Some((l, n)) if *l == light => *n += 1,
            _ => runs.push((light, 1)),
        }
    }
    let mut out: Vec<bool> = Vec::new();
    for (light, _) in runs.into_iter().filter(|&(_, n)| n >= 3) {
        if out.last() != Some(&light) {
            out.push(light);
        }
    }
    out
}

/// Seen from above, a 2 × 2 checker on each quad gives, along a row through the middle of
/// either row of squares, four alternating runs: the pattern restarts at the seam. Had
/// the seam's vertices one texture coordinate (the left quad's `s = 1` on the right quad
/// too), the right quad would show no squares along `s`.
#[test]
fn a_checker_follows_the_texture_coordinates_across_a_seam() {
    use subsurf::mesh::FaceVaryingInterpolation;
    let m = two_textured_quads();
    let options = Options {
        face_varying: FaceVaryingInterpolation::All,
        ..Options::default()
    };
    let tri = triangulated(&m);
    let geometries = [
        Geometry::Level(0),
        Geometry::Level(2),
        Geometry::Limit { rate: 16 },
    ];
    for (scheme, geometry) in geometries
        .iter()
        .flat_map(|&g| [(Scheme::CatmullClark, g), (Scheme::Loop, g)])
    {
        let opts = Render {
            width: 320,
            height: 200,
            view: (0.0, 89.0),
            geometry,
            shading: Shading::Flat,
            scheme,
            ..small(Paint::Checker { squares: 2 })
        };
        let mesh = if scheme == Scheme::Loop { &tri } else { &m };
        let img = render(mesh, &options, &opts).unwrap();
        for y in [80, 120] {
            let runs = checker_runs(&img, y, opts.background);
            assert_eq!(runs.len(), 4, "{geometry:?}, row {y}: {runs:?}");
        }
        // The two rows of squares are opposite colours.
        assert_ne!(
            checker_runs(&img, 80, opts.background)[0],
            checker_runs(&img, 120, opts.background)[0],
            "{geometry:?}"
        );
    }
}

/// The face-varying mode shapes the texture on the limit surface: the textured cube's
/// pictures differ between `all` (linear) and `none` (smooth everywhere).
#[test]
fn checker_pictures_differ_between_face_varying_modes() {
    use subsurf::mesh::FaceVaryingInterpolation;
    let path = format!(
        "{}/tests/golden/fvar/textured_cube.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let obj = parse_obj(&std::fs::read(&path).unwrap(), &path).unwrap();
    let draw = |mode| {
        let options = Options {
            face_varying: mode,
            ..obj.options.resolve(Options::default())
        };
        render(&obj.mesh, &options, &small(Paint::Checker { squares: 8 })).unwrap()
    };
    let (all, none) = (
        draw(FaceVaryingInterpolation::All),
        draw(FaceVaryingInterpolation::None),
    );
    let differ = all
        .pixels()
        .zip(none.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 100, "{differ} pixels differ");
}

#[test]
fn textures_need_texture_coordinates_and_the_meshs_own_surface() {
    let o = Options::default();
    let checker = small(Paint::Checker { squares: 4 });
    let err = render(&cube(), &o, &checker).unwrap_err();
    assert!(matches!(err, RenderError::NoTextureCoordinates), "{err}");
    let m = two_textured_quads();
    let bad = small(Paint::Checker { squares: 0 });
    assert!(matches!(
        render(&m, &o, &bad),
        Err(RenderError::BadSquares(0))
    ));
    let s = subsurf::limit::LimitSurface::new(&m, o).unwrap();
    let err = subsurf::render::render_surface(&m, &o, &checker, Some(&s)).unwrap_err();
    assert!(matches!(err, RenderError::TextureNeedsMeshSurface), "{err}");
}
